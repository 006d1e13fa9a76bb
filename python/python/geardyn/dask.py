"""Run a geardyn study as shards on Dask (``dask.distributed``).

geardyn cuts a study into shards whose partial results merge, byte for byte, into the outputs
of an unsharded run (see ``docs/scaling.md``). This module maps the shards onto a Dask
``Client`` -- a ``LocalCluster`` on one machine, or a cluster started by ``dask-jobqueue`` on
Slurm or PBS -- gathers the partial results and merges them with the same Rust code as
``geardyn merge``.

Dask is optional: importing this module without ``dask.distributed`` installed raises
``ImportError`` with the install line.
"""

from __future__ import annotations

import os
from typing import Any

from . import _geardyn, _unwrap

try:  # pragma: no cover - exercised only without dask
    import distributed  # noqa: F401
except ImportError as exc:  # pragma: no cover
    raise ImportError(
        "geardyn.dask needs dask.distributed: python3 -m pip install 'dask[distributed]'"
    ) from exc

__all__ = ["run_shard", "run_sharded"]


def run_shard(study_toml: str, index: int, count: int) -> str:
    """Compute shard ``index``/``count`` (1-based) of a study and return its partial result.

    The partial result is text (one header line and one line per point); it is what
    ``geardyn study FILE --shard i/n`` writes to ``out/shards/``.
    """
    return _unwrap(_geardyn.run_study_shard(study_toml, int(index), int(count)))


def run_sharded(
    study_toml: str,
    out_dir: str | os.PathLike[str],
    client: Any,
    shards: int,
) -> dict:
    """Run a study as ``shards`` Dask tasks on ``client`` and merge the results into ``out_dir``.

    Returns the study's JSON summary as a dict. The files written to ``out_dir`` are identical
    to those of ``geardyn.write_study(study_toml, out_dir)`` in one process.

    Raises ``ValueError`` for a shard count below 1 and ``geardyn.StudyError`` for an invalid
    study, a shard count above 10_000_000 or partial results that do not merge.
    """
    shards = int(shards)
    if shards < 1:
        raise ValueError(f"shards must be >= 1, got {shards}")
    futures = client.map(
        run_shard,
        [study_toml] * shards,
        range(1, shards + 1),
        [shards] * shards,
        pure=False,
    )
    parts = client.gather(futures)
    return _unwrap(_geardyn.merge_study(study_toml, list(parts), os.fspath(out_dir)))
