"""Dask overhead on a 1,000-point Liu rattle map (docs/performance.md, "Scaling").

    python python/examples/dask_overhead.py [SHARDS]     # from the repository root

Runs the map once in this process (2 rayon threads) and once as SHARDS Dask tasks on a
LocalCluster of 2 single-threaded worker processes, and checks that the files are identical.
"""
import sys
import time, os, shutil
import geardyn, geardyn.dask
from distributed import LocalCluster, Client
src = open("validation/examples/liu-rattle-map.toml").read()
src = src.replace('from = 100.0\nto = 250.0\nsteps = 16', 'from = 100.0\nto = 250.0\nsteps = 40')
src = src.replace('values = [5.0, 10.0, 20.0, 30.0, 40.0]', 'from = 5.0\nto = 40.0\nsteps = 25')
def main():
    for d in ["target/dask-bench-single", "target/dask-bench-sharded"]:
        shutil.rmtree(d, ignore_errors=True)
    os.environ["RAYON_NUM_THREADS"] = "2"
    t = time.perf_counter(); geardyn.write_study(src, "target/dask-bench-single"); single = time.perf_counter() - t
    os.environ["RAYON_NUM_THREADS"] = "1"
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as c, Client(c) as cl:
        t = time.perf_counter(); s = geardyn.dask.run_sharded(src, "target/dask-bench-sharded", cl, shards=int(sys.argv[1]) if len(sys.argv) > 1 else 4); dask_t = time.perf_counter() - t
    print(f"points={s['points']} single-process(2 threads)={single:.2f}s dask(2 workers x1, {len(sys.argv) > 1 and sys.argv[1] or 4} shards)={dask_t:.2f}s overhead={(dask_t/single-1)*100:.1f}%")
    import filecmp
    a=sorted(os.listdir("target/dask-bench-single")); b=sorted(os.listdir("target/dask-bench-sharded"))
    print("identical:", a==b and all(open(f"target/dask-bench-single/{f}","rb").read()==open(f"target/dask-bench-sharded/{f}","rb").read() for f in a))

if __name__ == '__main__':
    main()
