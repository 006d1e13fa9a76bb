"""Rattle state and peak-to-peak value of the Liu et al. 2021 NFG pair against pinion speed.

    python python/examples/liu_rattle_sweep.py [OUT_STEM]

Time-integrates the Table 1 model from rest at each speed (in parallel), then writes
OUT_STEM.svg (a step plot of rsv and the ppv curve) when matplotlib is installed, and
OUT_STEM.csv always. OUT_STEM defaults to ``liu_rattle_sweep``.
"""

import sys

import numpy as np

import geardyn


def main(stem="liu_rattle_sweep"):
    omega1 = np.linspace(100.0, 300.0, 41)  # pinion speed, rad/s
    liu = geardyn.Liu2021()  # Table 1, consistent readings
    sweep = liu.rattle_sweep(omega1, method="time-stepping")

    with open(f"{stem}.csv", "w", encoding="utf-8") as f:
        f.write("omega1 [rad/s],rsv [1],ppv [1]\n")
        for w, r, p in zip(sweep["omega1"], sweep["rsv"], sweep["ppv"]):
            f.write(f"{w:.6g},{r:.6g},{p:.6g}\n")
    print(f"wrote {stem}.csv")

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed: CSV only")
        return

    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(6, 5))
    ax1.step(sweep["omega1"], sweep["rsv"], where="mid", color="#0072B2",
             label="Liu 2021, time stepping")
    ax1.set_ylabel("rsv [1]")
    ax1.set_yticks([0, 1, 2])
    ax1.legend(loc="upper left")
    ax2.plot(sweep["omega1"], sweep["ppv"], color="#D55E00", label="Liu 2021, time stepping")
    ax2.set_xlabel("ω₁ [rad/s]")
    ax2.set_ylabel("ppv [1]")
    ax2.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(f"{stem}.svg")
    print(f"wrote {stem}.svg")


if __name__ == "__main__":
    main(*sys.argv[1:2])
