"""Run many independent calls, here or on a Dask cluster, and hand back each result as it
arrives.

``mega-sat batch`` and ``mega-sat bench`` both go through :func:`completed`: a local thread
pool by default (every call they make waits on a subprocess, so threads are enough), or the
workers of a ``dask.distributed`` scheduler given by its address.  Results come back in the
order they finish, so the caller can write each one at once and a stop loses nothing already
written.  Dask is imported only when a scheduler is given (the ``dask`` extra).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass
from typing import Any

from mega_sat.errors import PlannerError, UsageError


@dataclass(frozen=True)
class Outcome:
    """One finished call: its index in the list of calls, and its value or the exception it
    raised (on a Dask cluster also ``KilledWorker`` when its workers kept dying)."""

    index: int
    value: Any = None
    error: BaseException | None = None


def completed(
    fn: Callable[..., Any],
    calls: Sequence[tuple],
    *,
    jobs: int = 1,
    scheduler: Any = None,
) -> Iterator[Outcome]:
    """``fn(*args)`` for every ``args`` in ``calls``, yielded as they finish.

    ``scheduler``: ``None`` (``jobs`` threads here), a Dask scheduler address such as
    ``tcp://10.0.0.5:8786``, or a ``distributed.Client``.  Closing the iterator early (a time
    limit, Ctrl-C) cancels the calls not yet started."""
    if scheduler is None:
        yield from _local(fn, calls, max(1, jobs))
    else:
        yield from _dask(fn, calls, scheduler)


def _local(fn: Callable[..., Any], calls: Sequence[tuple], jobs: int) -> Iterator[Outcome]:
    ex = ThreadPoolExecutor(max_workers=jobs)
    pending = {ex.submit(fn, *args): i for i, args in enumerate(calls)}
    try:
        while pending:
            # a timed wait, so that a signal handler in the main thread runs promptly
            done, _ = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
            for fut in sorted(done, key=pending.__getitem__):
                i = pending.pop(fut)
                err = fut.exception()
                yield Outcome(i, None if err else fut.result(), err)
    finally:
        ex.shutdown(wait=False, cancel_futures=True)


def connect(scheduler: Any) -> tuple[Any, bool]:
    """A ``distributed.Client`` for ``scheduler`` and whether this call created it."""
    try:
        from distributed import Client
    except ImportError:
        raise UsageError(
            "--scheduler needs Dask's distributed package (install mega-sat with the 'dask' extra)"
        ) from None
    if isinstance(scheduler, Client):
        return scheduler, False
    if not isinstance(scheduler, str) or "://" not in scheduler:
        raise UsageError(f"--scheduler takes an address such as tcp://HOST:8786, got {scheduler!r}")
    try:
        return Client(scheduler, timeout=10), True
    except (OSError, TimeoutError) as e:
        raise PlannerError(f"cannot reach the Dask scheduler at {scheduler}: {e}") from None


def _dask(fn: Callable[..., Any], calls: Sequence[tuple], scheduler: Any) -> Iterator[Outcome]:
    from distributed import as_completed

    client, own = connect(scheduler)
    futures = {client.submit(fn, *args, pure=False): i for i, args in enumerate(calls)}
    try:
        for fut in as_completed(list(futures)):
            i = futures.pop(fut)
            try:
                yield Outcome(i, fut.result())
            except Exception as e:  # the call's own error, or KilledWorker
                yield Outcome(i, None, e)
    finally:
        if futures:
            client.cancel(list(futures))
        if own:
            client.close()
