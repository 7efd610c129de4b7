"""Reading a user's vehicle file, with one-line errors that name the file, line and field.

The schema is :class:`ecoplan.models.vehicle_schema.VehicleFile`; the YAML reader and the
error format are those of every ecoplan YAML file (:mod:`ecoplan.io.yaml`)::

    husky.yaml:7: inertia.mass_kg: expected a number > 0; got -5

>>> from ecoplan.io.vehicles import load_vehicle
>>> load_vehicle("husky-a200").terrains     # a shipped preset, by name
['asphalt', 'flooring', 'ice', 'sandy_loam', 'snow']
"""

from __future__ import annotations

import os
from pathlib import Path

from pydantic import ValidationError

from ecoplan.errors import InputError
from ecoplan.io.yaml import error_at, format_validation, read_text, read_yaml
from ecoplan.models.vehicle_schema import VehicleFile, limit_problem
from ecoplan.models.vehicles import Vehicle, shipped_names, shipped_vehicle

__all__ = ["MAX_VEHICLE_FILE_BYTES", "load_vehicle", "parse_vehicle"]

#: Largest vehicle file accepted [bytes].
MAX_VEHICLE_FILE_BYTES = 1_000_000


def parse_vehicle(text: str, source: str = "<string>") -> Vehicle:
    """Validate the text of a vehicle file.

    Parameters
    ----------
    text : str
        YAML document (see :mod:`ecoplan.models.vehicle_schema` for the schema).
    source : str
        Name used in error messages.

    Returns
    -------
    Vehicle

    Raises
    ------
    InputError
        Invalid YAML or a value outside the schema: one line naming the file, the line,
        the field and the accepted range.
    """
    data, lines = read_yaml(text, source, kind="vehicle file")
    try:
        spec = VehicleFile.model_validate(data)
    except ValidationError as exc:
        raise InputError(format_validation(exc, source, lines, VehicleFile)) from None
    problem = limit_problem(spec)
    if problem is not None:
        raise error_at(source, lines, problem[0], problem[1])
    vehicle = Vehicle(spec, source)
    for terrain in vehicle.terrains:  # the parameter classes' own checks, line-numbered
        try:
            vehicle.params(terrain)
        except InputError as exc:
            line = lines.line(("terrains", terrain))
            where = f"{source}:{line}" if line is not None else source
            raise InputError(f"{where}: terrains.{terrain}: {exc}") from None
    return vehicle


def load_vehicle(path_or_name: str | os.PathLike[str]) -> Vehicle:
    """A vehicle from a file, or a shipped preset by name.

    Parameters
    ----------
    path_or_name : str or path
        A vehicle file (``husky.yaml``) or the name of a shipped vehicle
        (``husky-a200``; see :func:`ecoplan.models.vehicles.shipped_names`).

    Returns
    -------
    Vehicle

    Raises
    ------
    InputError
        No such file or preset, or an invalid file (one line: file, line, field, range).
    """
    text = os.fspath(path_or_name)
    path = Path(text).expanduser()
    if not path.exists() and text in shipped_names():
        return shipped_vehicle(text)
    if not path.exists() and not text.endswith((".yaml", ".yml")):
        raise InputError(
            f"no vehicle file or preset {text!r}; presets: {', '.join(shipped_names())}"
        )
    body = read_text(path, MAX_VEHICLE_FILE_BYTES, kind="vehicle file")
    return parse_vehicle(body, str(path))
