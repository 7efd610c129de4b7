"""One interface to run many independent cases: local processes or a Dask cluster.

``ecoplan compare`` and ``ecoplan bench`` sweep over cases (waypoint sets, planners,
seeds) that share nothing.  :func:`make_executor` returns

* a :class:`LocalExecutor` -- ``concurrent.futures.ProcessPoolExecutor`` on this
  machine (or plain in-process calls with ``workers=1``), by default;
* a :class:`DaskExecutor` -- a ``dask.distributed`` client connected to the scheduler
  address the user passes (``pip install 'ecoplan[dask]'``; imported lazily).

Both return the results **in the order of the cases**, whatever order they finish in,
and call an optional ``on_done(n_done, n_total)`` callback for a progress bar.  The
function and its cases must be picklable (module-level functions, frozen dataclasses).

>>> with make_executor(workers=1) as ex:
...     ex.map(abs, [-2, 3, -5])
[2, 3, 5]
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from types import TracebackType
from typing import Any, Protocol, TypeVar

from ecoplan.errors import InputError

__all__ = ["CaseExecutor", "DaskExecutor", "LocalExecutor", "ProgressFn", "make_executor"]

T = TypeVar("T")
R = TypeVar("R")

#: Progress callback: ``on_done(n_done, n_total)``.
ProgressFn = Callable[[int, int], None]


class CaseExecutor(Protocol):
    """What ``compare`` and ``bench`` need: an ordered map over independent cases."""

    @property
    def description(self) -> str:
        """Where the cases run, for reports (``"4 local processes"``, ``"dask tcp://..."``)."""
        ...

    def map(
        self, fn: Callable[[T], R], cases: Iterable[T], on_done: ProgressFn | None = None
    ) -> list[R]:
        """Run ``fn`` on every case; results in case order; the first error is raised."""
        ...

    def close(self) -> None:
        """Release workers or the cluster connection."""
        ...

    def __enter__(self) -> CaseExecutor: ...

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None: ...


class _ContextMixin:
    def close(self) -> None:
        """Release resources (nothing by default)."""

    def __enter__(self: Any) -> Any:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


class LocalExecutor(_ContextMixin):
    """Cases on this machine: a process pool, or in-process when ``workers == 1``.

    Parameters
    ----------
    workers : int, optional
        Number of worker processes; default ``os.cpu_count()``.  With 1 (or a single
        case) the cases run in this process, which avoids the pool's start-up cost.
    """

    def __init__(self, workers: int | None = None) -> None:
        n = os.cpu_count() or 1 if workers is None else workers
        if n < 1:
            raise InputError(f"workers = {n} must be >= 1")
        self.workers = n

    @property
    def description(self) -> str:
        """Where the cases run."""
        return "in-process" if self.workers == 1 else f"{self.workers} local processes"

    def map(
        self, fn: Callable[[T], R], cases: Iterable[T], on_done: ProgressFn | None = None
    ) -> list[R]:
        """Run ``fn`` on every case; results in case order; the first error is raised."""
        items = list(cases)
        total = len(items)
        if self.workers == 1 or total <= 1:
            out = []
            for i, item in enumerate(items):
                out.append(fn(item))
                if on_done is not None:
                    on_done(i + 1, total)
            return out
        with ProcessPoolExecutor(max_workers=min(self.workers, total)) as pool:
            futures = [pool.submit(fn, item) for item in items]
            _wait_all(futures, on_done)
            return [f.result() for f in futures]


def _wait_all(futures: Sequence[Future[Any]], on_done: ProgressFn | None) -> None:
    pending = set(futures)
    total = len(futures)
    while pending:
        done, pending = wait(pending, return_when=FIRST_COMPLETED)
        for f in done:
            if f.exception() is not None:
                for other in pending:
                    other.cancel()
                raise f.exception()  # type: ignore[misc]
        if on_done is not None:
            on_done(total - len(pending), total)


class DaskExecutor(_ContextMixin):
    """Cases on a Dask distributed cluster.

    Parameters
    ----------
    address : str
        Scheduler address, e.g. ``tcp://10.0.0.5:8786`` (or a ``LocalCluster``'s
        ``scheduler_address``).
    timeout_s : float
        How long to wait for the scheduler before giving up.

    Raises
    ------
    InputError
        Dask is not installed, the address is malformed, or the scheduler cannot be reached.
    """

    def __init__(self, address: str, timeout_s: float = 10.0) -> None:
        try:
            dist: Any = importlib.import_module("distributed")
        except ImportError:
            raise InputError(
                "a scheduler address needs Dask: pip install 'ecoplan[dask]'"
            ) from None
        try:  # a malformed address is refused before a client exists (a half-built one
            # stalls the interpreter's exit for 20 s and prints a traceback from its __del__)
            scheme, _ = dist.comm.parse_address(address)
            if scheme not in ("inproc", "ucx"):  # addresses without host:port
                dist.comm.get_address_host_port(address)
        except ValueError as exc:
            raise InputError(
                f"scheduler address {address!r}: {exc}; expected e.g. tcp://10.0.0.5:8786"
            ) from None
        try:
            self._client: Any = dist.Client(address, timeout=timeout_s, set_as_default=False)
        except (OSError, TimeoutError, ValueError) as exc:
            raise InputError(f"cannot reach the Dask scheduler at {address!r}: {exc}") from None
        self.address = address

    @property
    def description(self) -> str:
        """Where the cases run."""
        return f"dask {self.address}"

    def map(
        self, fn: Callable[[T], R], cases: Iterable[T], on_done: ProgressFn | None = None
    ) -> list[R]:
        """Run ``fn`` on every case; results in case order; the first error is raised."""
        as_completed: Any = importlib.import_module("distributed").as_completed
        items = list(cases)
        futures = self._client.map(fn, items, pure=False)
        total = len(futures)
        for n, fut in enumerate(as_completed(futures, loop=self._client.loop), start=1):
            if fut.status == "error":
                self._client.cancel(futures)
                fut.result()  # raises the case's exception
            if on_done is not None:
                on_done(n, total)
        return list(self._client.gather(futures))

    def close(self) -> None:
        """Disconnect from the scheduler (the cluster keeps running)."""
        self._client.close()


def make_executor(scheduler: str | None = None, workers: int | None = None) -> CaseExecutor:
    """The executor for a sweep: Dask when ``scheduler`` is given, else local processes.

    Parameters
    ----------
    scheduler : str, optional
        Dask scheduler address; None runs on this machine.
    workers : int, optional
        Local worker processes (ignored with a scheduler); default: all cores.

    Returns
    -------
    CaseExecutor
        Use as a context manager so workers are released.
    """
    if scheduler:
        return DaskExecutor(scheduler)
    return LocalExecutor(workers)
