r"""The corrected-model file: its format tag, its schema (pydantic) and its reader.

:func:`ecoplan.diagnose.corrected.save_corrected_model` writes the file and
:func:`ecoplan.diagnose.corrected.load_corrected_model` builds the model from what
:func:`read_corrected_model_file` returns.  JSON is read as YAML (JSON is a subset of it), so
both suffixes get the YAML reader's safety limits and line numbers::

    corrected_model.json:9: effect.params.c_n_s_per_m: expected a number; got 'big'

>>> spec, lines = parse_corrected_model(
...     '{"format": "ecoplan-corrected-model/1", "vehicle": "pioneer-3at",\n'
...     ' "terrain": "asphalt", "params": {}, "effect": {"name": "none"}}', "m.json")
>>> spec.vehicle, spec.effect.name, lines.line(("terrain",))
('pioneer-3at', 'none', 2)
"""

from __future__ import annotations

import os
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, StrictFloat, ValidationError

from ecoplan.errors import InputError
from ecoplan.io.yaml import LineMap, format_validation, read_text, read_yaml

__all__ = [
    "FORMAT",
    "MAX_CORRECTED_MODEL_BYTES",
    "CorrectedEffectEntry",
    "CorrectedModelFile",
    "parse_corrected_model",
    "read_corrected_model_file",
]

#: Format tag of the corrected-model file.
FORMAT = "ecoplan-corrected-model/1"

#: Largest corrected-model file accepted [bytes].
MAX_CORRECTED_MODEL_BYTES = 1_000_000


class CorrectedEffectEntry(BaseModel):
    """The ``effect`` section: the verdict's effect and its fitted physical parameters.

    Attributes
    ----------
    name : str
        Effect name (``"none"`` when the verdict named no effect).
    params : dict of str to float or None
        Fitted parameters, units in the names: numbers (a quoted number is refused);
        ``null`` stands for an infinite value (a saturation without cap).
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str = Field(default="none", pattern=r"^[a-z][a-z0-9_]*$")
    params: dict[str, StrictFloat | None] = Field(default_factory=dict)


class CorrectedModelFile(BaseModel):
    """Schema of the corrected-model file (unknown keys are errors).

    Attributes
    ----------
    format : str
        Must be :data:`FORMAT`.
    vehicle : str
        Vehicle preset the model was calibrated from.
    terrain : str or None
        Terrain preset.
    kind : {"tracked", "wheeled"} or None
        Body kind, written for the reader; checked against the vehicle when given.
    params : dict
        Calibrated parameters, overriding the preset's (checked by the parameter class).
    effect : CorrectedEffectEntry
        The fitted effect.
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    format: Literal["ecoplan-corrected-model/1"]  # = FORMAT (a test checks)
    vehicle: str = Field(min_length=1)
    terrain: str | None = None
    kind: Literal["tracked", "wheeled"] | None = None
    params: dict[str, Any]
    effect: CorrectedEffectEntry = Field(default_factory=CorrectedEffectEntry)


def parse_corrected_model(text: str, source: str) -> tuple[CorrectedModelFile, LineMap]:
    """Validate the text of a corrected-model file (JSON or YAML).

    Parameters
    ----------
    text : str
        The document.
    source : str
        File name for the messages.

    Returns
    -------
    spec : CorrectedModelFile
        The validated sections.
    lines : LineMap
        Line of every field, for the caller's own messages.

    Raises
    ------
    InputError
        Not JSON/YAML, or a field outside the schema: one line naming the file, the line and
        the field.
    """
    data, lines = read_yaml(text, source, kind="corrected-model file")
    try:
        return CorrectedModelFile.model_validate(data), lines
    except ValidationError as exc:
        raise InputError(format_validation(exc, source, lines, CorrectedModelFile)) from None


def read_corrected_model_file(
    path: str | os.PathLike[str],
) -> tuple[CorrectedModelFile, LineMap]:
    """Read and validate a corrected-model file.

    Parameters
    ----------
    path : str or path
        The file (``.json``, ``.yaml`` or ``.yml``).

    Returns
    -------
    spec : CorrectedModelFile
        The validated sections.
    lines : LineMap
        Line of every field.

    Raises
    ------
    InputError
        Missing, unreadable, too large, or invalid (see :func:`parse_corrected_model`).
    """
    source = os.fspath(path)
    text = read_text(source, MAX_CORRECTED_MODEL_BYTES, InputError, kind="corrected-model file")
    return parse_corrected_model(text, source)
