"""One typed convergence status for every result: :class:`SolverStatus`.

Every solution of a model (normal, tangential, the vertical balance of a
wheel-rail case) carries a :class:`SolverStatus`; a case result combines those of
its parts with :meth:`SolverStatus.combine`, so that no unconverged part can hide
behind a converged whole.  ``converged`` says whether the numbers are a solution of
the problem as posed; ``warnings`` say where a converged result leaves the range in
which its models hold (a contact truncated by its grid, a wheel climbing its
flange, a patch large against the radii of curvature).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable


@dataclass(frozen=True)
class SolverStatus:
    """Whether an iterative solution met its tolerance, and what to know about it.

    Attributes
    ----------
    converged : bool
        True when the solution meets its solver's tolerance (or needs no iteration).
    message : str
        Why it did not converge ("" when it did).
    iterations : int
        Iterations the solver took (0 where it does not iterate).
    warnings : tuple of str
        Conditions under which a converged result should not be trusted as it is.
    """

    converged: bool = True
    message: str = ""
    iterations: int = 0
    warnings: tuple = ()

    @classmethod
    def failed(cls, message: str, iterations: int = 0, warnings: Iterable[str] = ()
               ) -> "SolverStatus":
        """An unconverged status with its reason."""
        return cls(False, message, int(iterations), tuple(warnings))

    def with_warnings(self, *warnings: str) -> "SolverStatus":
        """This status with more warnings (duplicates dropped, order kept)."""
        new = tuple(w for w in warnings if w and w not in self.warnings)
        return SolverStatus(self.converged, self.message, self.iterations,
                            self.warnings + new)

    @classmethod
    def combine(cls, parts: Iterable[tuple[str, "SolverStatus | None"]]) -> "SolverStatus":
        """The status of a whole made of labelled parts: converged where every part
        is, with the messages and warnings of the parts prefixed by their labels
        (``None`` parts are skipped); iterations are summed."""
        ok, messages, warnings, iterations = True, [], [], 0
        for label, status in parts:
            if status is None:
                continue
            iterations += status.iterations
            prefix = f"{label}: " if label else ""
            if not status.converged:
                ok = False
                messages.append(prefix + (status.message or "not converged"))
            for w in status.warnings:
                text = prefix + w
                if text not in warnings:
                    warnings.append(text)
        return cls(ok, "; ".join(messages), iterations, tuple(warnings))

    def to_dict(self) -> dict:
        """JSON form: ``converged``, ``message``, ``iterations``, ``warnings``."""
        return {"converged": self.converged, "message": self.message,
                "iterations": self.iterations, "warnings": list(self.warnings)}
