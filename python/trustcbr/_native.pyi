"""Type stubs of the extension module ``trustcbr._native`` (the Rust side of trustcbr)."""

from typing import Any, Callable, Dict, List, Optional, Tuple

__version__: str

class TrustcbrError(Exception):
    """An error of trustcbr, with the message the command-line tool gives for it."""

class Session:
    """One controller's adapter over a case base (``trustcbr serve`` for one controller)."""

    def __init__(
        self,
        domain: str,
        cases: str,
        seed: int = 0,
        arm: Optional[str] = None,
        mission: bool = False,
    ) -> None: ...
    def request(self, line: str) -> str:
        """Handles one protocol request (JSON text); returns the reply's JSON text."""
    @property
    def location(self) -> str: ...
    @property
    def writable(self) -> bool: ...

def scenarios() -> List[str]: ...
def operators(scenario: str) -> List[str]: ...
def space(scenario: str) -> Dict[str, Any]: ...
def simulate(scenario: str, behavior: Any, operator: str, seed: int = 0) -> Any: ...
def landscape(
    scenario: str, operator: str, runs: int = 100, seed: int = 0
) -> Tuple[List[float], List[int], List[str]]: ...
def default_suite() -> str: ...
def builtin_arms() -> List[str]: ...
def strategies() -> List[Any]: ...
def run_suite(
    kind: str,
    text: str,
    origin: str,
    *,
    out: Optional[str] = None,
    trials: Optional[int] = None,
    seed: Optional[int] = None,
    landscape_runs: Optional[int] = None,
    arms: Optional[List[str]] = None,
    threads: Optional[int] = None,
    python_arms: List[Tuple[str, Callable[..., Any], bool]] = ...,
    save_cases: Optional[str] = None,
    cases: Optional[str] = None,
) -> Tuple[str, str, str, str]: ...
def check_searcher(factory: Callable[..., Any]) -> None: ...
def rasterize(svg: str) -> Tuple[int, int, bytes]:
    """An SVG drawing as pixels: width, height and RGBA bytes row by row."""
