"""Running a sweep's tasks on a Dask distributed cluster.

The workers must have pound installed (the same version: it is part of every case's hash)
and see the base model, the records and the output folder at the same paths as the
machine that starts the sweep (a shared file system): each worker reads its case's inputs
and writes its case file itself. Dask's nanny starts workers with OMP, MKL and OpenBLAS at
one thread (``distributed.nanny.pre-spawn-environ``); pound's compiled kernels are serial.
Give each worker one thread (``dask worker --nthreads 1``) or as many as its cores: a case
holds the GIL while it integrates, so threads of one worker run cases one at a time.

A worker that dies while running a case is replaced by Dask and the case retried up to
``distributed.scheduler.allowed-failures`` times (3 by default), then recorded as failed.
"""

from __future__ import annotations

import uuid
from pathlib import Path
from typing import Any, Iterable, Iterator

from ..errors import InputError
from .pool import Outcome, Task

CONNECT_TIMEOUT_S = 30.0


class DaskExecutor:
    """Submits tasks to a Dask scheduler through a client, yields outcomes as they finish."""

    def __init__(self, client: Any, owns_client: bool = False):
        self.client = client
        self._owns = owns_client

    @classmethod
    def connect(cls, address: str | None = None, scheduler_file: str | Path | None = None) -> "DaskExecutor":
        """A client of the scheduler at `address` (tcp://host:8786) or in `scheduler_file`."""
        try:
            from distributed import Client
        except ImportError:  # pragma: no cover - a dependency of pound
            raise InputError("dask.distributed is not installed: pip install 'dask[distributed]'",
                             field="--scheduler") from None  # fmt: skip
        option = "--scheduler" if address else "--scheduler-file"
        if scheduler_file is not None and not Path(scheduler_file).is_file():
            raise InputError("no such file (a scheduler file is written by `dask scheduler --scheduler-file`)",
                             file=scheduler_file, field=option)  # fmt: skip
        try:
            if address:
                client = Client(address, timeout=CONNECT_TIMEOUT_S)
            else:
                client = Client(scheduler_file=str(scheduler_file), timeout=CONNECT_TIMEOUT_S)
        except (OSError, TimeoutError, ValueError) as exc:
            target = address or scheduler_file
            raise InputError(f"cannot reach the Dask scheduler at {target}: {exc}", field=option) from None
        return cls(client, owns_client=True)

    @property
    def description(self) -> str:
        threads = sum(self.client.nthreads().values())
        return f"the Dask cluster at {self.client.scheduler.address} ({threads} worker threads)"

    def run(self, tasks: Iterable[Task]) -> Iterator[Outcome]:
        """Submit the tasks, yield each outcome as it finishes. At most twice as many tasks as
        the cluster has worker threads are submitted and not yet taken: a worker holds the
        result of a task it finished until it is taken, and a district's groups return a
        hundred buildings' histories each (10,000 buildings on 2 workers, every group
        submitted at once: the workers grew to 4.7 GB each while the results waited)."""
        from distributed import as_completed

        todo = iter(tasks)
        keys: dict[Any, Any] = {}
        finished = as_completed()

        def submit_one() -> None:
            for key, function, args in todo:
                name = f"pound-{function.__name__}-{uuid.uuid4().hex}"
                future = self.client.submit(function, *args, key=name, pure=False)
                keys[future] = key
                finished.add(future)
                return

        for _ in range(max(2, 2 * sum(self.client.nthreads().values()))):
            submit_one()
        for future in finished:
            key = keys.pop(future)
            submit_one()  # the next task runs while this outcome is taken
            try:
                yield key, True, future.result()
            except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker: this case failed
                yield key, False, f"{type(exc).__name__} on the Dask cluster: {exc}"
            finally:
                future.release()

    def close(self) -> None:
        if self._owns:
            self.client.close()

    def __enter__(self) -> "DaskExecutor":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
