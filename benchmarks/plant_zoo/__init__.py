"""An independent plant zoo for the blind diagnosis benchmark (issue 12, item 6).

Skid-steer robots simulated directly from the two papers -- Morales et al. 2009 (tracked,
Auriga-beta) and Chuy et al. 2009 (wheeled, Pioneer 3-AT) -- with numpy and scipy only.  It
imports nothing from ``ecoplan`` and was written without reading ecoplan's model code, so
that it cannot share a convention with the library by accident.  Logs are written in the
README's CSV log format, the contract between the zoo and the diagnosis.

Variant ``h`` (friction growing with slip as Coulomb plus a viscous term) is the development
sibling of ``c`` (a power law in the slip speed): work on the friction law is measured on h,
so that c, held out, stays a blind check.  Variant ``i`` (the wheeled paper literally, on its
Table II vinyl floor) is ``g``'s (Table I, asphalt) in the same way.

Modules: :mod:`.tracked` (eqs. 1-23 of the tracked paper), :mod:`.wheeled` (eqs. 12-15,
Tables I-II), :mod:`.drive` (operator-like commands), :mod:`.plant` (variants, injected
effects, logging).
"""

from .plant import (
    EFFECTS,
    IN_LIBRARY,
    OUT_OF_LIBRARY,
    VARIANTS,
    Case,
    expected_verdict,
    make_case,
    write_log,
)

__all__ = [
    "EFFECTS",
    "IN_LIBRARY",
    "OUT_OF_LIBRARY",
    "VARIANTS",
    "Case",
    "expected_verdict",
    "make_case",
    "write_log",
]
