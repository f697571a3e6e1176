"""A parameter sweep on Dask distributed: the quasi-static cantilever of
`scenes/validation/cantilever_small_load.toml` for a range of thicknesses, one independent run each,
gathered into one table and plotted.

    python examples/python/sweep.py [--workers 2] [--scheduler ADDRESS] [--out out/python_sweep]

Without `--scheduler` the runs go to a LocalCluster of `--workers` processes; with it, to that
scheduler (a cluster started by `dask scheduler`/`dask worker`, or by dask-jobqueue). Without
dask installed they run here one after the other. The table is written as CSV; Matplotlib, if
installed, plots the tip deflection against the thickness with the Euler–Bernoulli line
w = F L³ / (3 E I), I = b h³ / 12.
"""

import argparse
from pathlib import Path

import numpy as np

from cosserat import sweep

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "validation" / "cantilever_small_load.toml"
# The scene's cantilever: 1 m × 0.1 m, E = 1 GPa, ν = 0, 2.5 mN at the tip.
LENGTH, WIDTH, E, FORCE = 1.0, 0.1, 1e9, 2.5e-3


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--scheduler", help="address of a running Dask scheduler")
    parser.add_argument("--out", type=Path, default=Path("out/python_sweep"))
    args = parser.parse_args()

    thicknesses = [5e-3, 7e-3, 10e-3, 14e-3, 20e-3]
    runs = sweep.grid(SCENE, args.out, **{"material.thickness": thicknesses})

    try:
        import distributed
    except ImportError:
        print("dask.distributed is not installed: running here")
        rows = sweep.run_local(runs)
    else:
        if args.scheduler:
            with distributed.Client(args.scheduler) as client:
                rows = sweep.run_sweep(runs, client)
        else:
            with distributed.LocalCluster(n_workers=args.workers, threads_per_worker=1) as cluster, \
                    distributed.Client(cluster) as client:
                rows = sweep.run_sweep(runs, client)

    args.out.mkdir(parents=True, exist_ok=True)
    sweep.to_csv(rows, args.out / "sweep.csv")
    print(f"{'h [mm]':>8} {'status':>8} {'tip w [mm]':>12} {'beam [mm]':>10} {'steps':>6} {'wall [s]':>9}")
    tips = []
    for h, row in zip(thicknesses, rows):
        w = row.get("probe.tip_mid.uz", float("nan"))
        beam = FORCE * LENGTH**3 / (3 * E * WIDTH * h**3 / 12)
        tips.append((h, w, beam))
        print(f"{h * 1e3:8.1f} {row['status']:>8} {w * 1e3:12.4f} {beam * 1e3:10.4f} "
              f"{row.get('n_steps', 0):6d} {row.get('wall_seconds', float('nan')):9.2f}")
    print(f"table: {args.out / 'sweep.csv'}")

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot")
        return
    h, w, beam = np.array(tips).T
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.loglog(h * 1e3, np.abs(w) * 1e3, "o-", label="Cosserat shell")
    ax.loglog(h * 1e3, beam * 1e3, "k--", label="Euler–Bernoulli beam")
    ax.set_xlabel("thickness h [mm]")
    ax.set_ylabel("tip deflection [mm]")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out / "sweep.png")
    print(f"plot: {args.out / 'sweep.png'}")


if __name__ == "__main__":
    main()
