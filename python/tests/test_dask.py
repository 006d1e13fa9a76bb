"""The Dask path: a sharded 2-D map merged from several worker processes equals one process."""

from __future__ import annotations

import filecmp
import os
from pathlib import Path

import pytest

import distributed  # noqa: E402  (CI installs dask[distributed]; a missing Dask fails the test)

import geardyn  # noqa: E402
import geardyn.dask  # noqa: E402

STUDY = """
name = "dask-map"
model = "karpov2017-kinematics"

[sweep]
parameter = "b"
from = 0.001
to = 0.02
steps = 7

[sweep2]
parameter = "xi"
values = [1.5, 2.0, 3.0]

[solver]
method = "kinematics"
"""


def _files(d: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(d.iterdir()) if p.is_file()}


def test_sharded_map_on_local_cluster_equals_single_process(tmp_path: Path) -> None:
    single = tmp_path / "single"
    sharded = tmp_path / "sharded"
    geardyn.write_study(STUDY, os.fspath(single))
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        summary = geardyn.dask.run_sharded(STUDY, sharded, client, shards=5)
    assert summary["points"] == 21
    a, b = _files(single), _files(sharded)
    assert sorted(a) == sorted(b)
    for name in a:
        assert a[name] == b[name], name


def test_shard_count_is_checked() -> None:
    with pytest.raises(ValueError):
        geardyn.dask.run_sharded(STUDY, "unused", client=None, shards=0)
