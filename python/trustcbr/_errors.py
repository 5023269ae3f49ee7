"""The exceptions of trustcbr (the Rust extension raises these very classes)."""

from __future__ import annotations

from typing import Any, Dict, List, Optional


class TrustcbrError(Exception):
    """An error of trustcbr, with the message the command-line tool gives for it."""


class SearcherCheckError(TrustcbrError):
    """A searcher broke a rule of the conformance kit (:func:`trustcbr.check_searcher`).

    ``rule`` names the rule; ``space`` is the space it was checked on (as a factory is
    given it), ``evaluated`` the episode's behaviors up to the failure, ``proposal`` what
    ``propose`` returned there (``None`` for ``None``), ``seed`` the case's seed; the
    message says what went wrong, on which case, and what to change.
    """

    def __init__(
        self,
        message: str,
        *,
        rule: str,
        space: Dict[str, Any],
        evaluated: List[Dict[str, Any]],
        proposal: Optional[Dict[str, Any]],
        seed: int,
    ) -> None:
        super().__init__(message)
        self.rule = rule
        self.space = space
        self.evaluated = evaluated
        self.proposal = proposal
        self.seed = seed
