"""Test-suite settings shared by every test module.

On CI (``CI`` set, as ``.ci/run`` is run) hypothesis draws its examples from a fixed seed, so a
CI run is repeatable and a landing never hangs on a new random draw; local runs stay random and
keep exploring (a failure found there is replayed from ``.hypothesis/``).
"""

from __future__ import annotations

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
