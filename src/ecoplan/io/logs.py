"""Read logs from any supported source: CSV files, BorealTC runs and ROS 2 bags."""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from pathlib import Path

from ecoplan.dynamics.log import Log
from ecoplan.errors import LogFormatError
from ecoplan.io.borealtc import load_borealtc, load_borealtc_runs
from ecoplan.io.logcsv import read_log_csv
from ecoplan.io.rosbag import TopicMap, load_topic_map, read_rosbag

__all__ = ["read_logs"]


def read_logs(
    paths: Iterable[str | os.PathLike[str]],
    *,
    topic_map: TopicMap | None = None,
    bus_voltage_v: float = 24.0,
) -> list[Log]:
    """Read several logs (one run each) of any supported source; errors name the source.

    Each entry is one of:

    * a CSV file in the ecoplan format (:func:`read_log_csv`);
    * ``borealtc:TERRAIN`` (every run) or ``borealtc:TERRAIN/RUN`` -- BorealTC runs
      (:func:`load_borealtc`, with ``bus_voltage_v``);
    * a ROS 2 bag (a directory holding ``metadata.yaml``, or an ``.mcap``/``.db3`` file),
      read with ``topic_map`` or, when it is None, with the topic map in the file
      ``<bag>.topics.yaml`` beside the bag (:func:`load_topic_map`).

    Parameters
    ----------
    paths : iterable of path-like or str
        The sources, one run each (``borealtc:TERRAIN`` gives every run of a terrain).
    topic_map : TopicMap, optional
        Topic map of every bag; None = each bag's ``<bag>.topics.yaml``.
    bus_voltage_v : float
        Assumed bus voltage of the BorealTC runs [V].

    Returns
    -------
    list of Log
        The logs, in the order given.

    Raises
    ------
    LogFormatError
        No entries, a malformed source, or a bag without a topic map.
    """
    seq: Sequence[str | os.PathLike[str]] = list(paths)
    if not seq:
        raise LogFormatError("no log files given")
    out: list[Log] = []
    for entry in seq:
        text = os.fspath(entry)
        if text.lower().startswith("borealtc:"):
            terrain, _, run = text.split(":", 1)[1].partition("/")
            if run:
                out.append(load_borealtc(terrain, run, bus_voltage_v))
            else:
                out.extend(load_borealtc_runs(terrain, bus_voltage_v))
            continue
        path = Path(text)
        is_bag = (path.is_dir() and (path / "metadata.yaml").is_file()) or path.suffix in (
            ".mcap",
            ".db3",
        )
        out.append(_read_bag(path, topic_map) if is_bag else read_log_csv(path))
    return out


def _read_bag(path: Path, topic_map: TopicMap | None) -> Log:
    """A bag with the given topic map, else the one in ``<bag>.topics.yaml``."""
    if topic_map is None:
        side = path.with_name(path.name + ".topics.yaml")
        if not side.is_file():
            raise LogFormatError(
                f"{path}: a ROS 2 bag needs a topic map; none given and no {side.name} "
                "beside the bag"
            )
        topic_map = load_topic_map(side)
    return read_rosbag(path, topic_map)
