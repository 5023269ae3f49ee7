"""Type stubs of the extension module ``trustcbr._native`` (the Rust side of trustcbr; a
plug-in's module made by ``catalog_module!`` has the same functions). The package calls
it through :mod:`trustcbr`; these say what crosses."""

from typing import Any, Callable, Dict, List, Optional, Tuple

__version__: str
tool: str
RECOMMENDED_ARM: str

class Session:
    """One controller's adapter over a case base (``trustcbr serve`` for one controller)."""

    def request(self, line: str) -> str:
        """Handles one protocol request (JSON text); returns the reply's JSON text."""
    @property
    def location(self) -> str: ...
    @property
    def writable(self) -> bool: ...

class Episodes:
    """The Gymnasium environment's episodes, stepped natively."""

    def reset(self, name: str, seed: int) -> None: ...
    def step(self, action: List[int]) -> Dict[str, Any]: ...
    def render(self, action: List[int], seed: int) -> Optional[str]: ...

class Report:
    """A finished run, kept to write its report folder later (``Results.save``)."""

    def save(self, out: str) -> List[str]:
        """Writes the report folder ``out``, byte for byte the one the run's ``out=``
        writes; returns the files written."""

def scenarios() -> List[str]: ...
def operators(scenario: str) -> List[str]: ...
def space(scenario: str) -> Dict[str, Any]: ...
def simulate(scenario: str, behavior: Any, operator: str, seed: int) -> Any: ...
def landscape(
    scenario: str,
    operator: str,
    runs: int,
    seed: int,
    progress: Optional[Callable[[int, int, float, Optional[str]], Any]],
) -> Tuple[List[float], List[int], List[str]]: ...
def default_suite() -> str: ...
def builtin_arms() -> List[str]: ...
def strategies() -> List[Any]: ...
def run_suite(request: Dict[str, Any]) -> Dict[str, Any]:
    """Runs a suite (``kind``, ``text``, ``origin``, ``base``, ``expect``, the options, the
    Python arms and the progress callback); returns ``kind``, ``records``, ``summary``,
    ``table``, ``paper_table``, ``config`` and the :class:`Report`."""

def read_config(kind: str, text: str, origin: str) -> str: ...
def explain(
    report: str,
    experiment: str,
    arm: str,
    trial: int,
    cases: Optional[str],
    python_arms: List[Tuple[str, Callable[..., Any], bool]],
) -> Tuple[str, str, List[str]]: ...
def check_searcher(
    factory: Callable[..., Any], scenario: Optional[str]
) -> Optional[Dict[str, Any]]: ...
def session(
    domain: str,
    cases: str,
    seed: int,
    arm: Optional[str],
    strategy: Optional[Tuple[str, Callable[..., Any], bool]],
    mission: bool,
    competence: Optional[float],
    detect_changes: bool,
) -> Session: ...
def rasterize(svg: str) -> Tuple[int, int, bytes]:
    """An SVG drawing as pixels: width, height and RGBA bytes row by row."""

def episodes(
    scenario: str, operators: List[str], max_commands: int, attention: float
) -> Episodes: ...
