"""The twisting strip driven from Python: a controller turns the right end with a smooth start
(instead of the scene's constant 360°/s) and the run records how the strip's middle follows.

    python examples/python/twisting_strip.py [--end 1.0] [--out out/python_strip]

With `--out`, the run writes the same files as `cosserat run` (frames, probes.csv, summary.json);
without, it steps in memory and prints the middle node's height every 0.1 s. Matplotlib, if
installed, plots the end angle and the middle's height (`--plot strip.png`).
"""

import argparse
import math
from pathlib import Path

import numpy as np

import cosserat

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "twisting_strip.toml"


def angle(t, ramp=0.5, speed=2 * math.pi):
    """End angle [rad]: the speed reached smoothly over `ramp` seconds, then held."""
    if t < ramp:
        return speed * t * t / (2 * ramp)
    return speed * (t - ramp / 2)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--end", type=float, default=1.0, help="end time [s]")
    parser.add_argument("--out", type=Path, help="write the run's outputs here")
    parser.add_argument("--plot", type=Path, help="plot to this PNG (needs matplotlib)")
    args = parser.parse_args()

    sim = cosserat.Simulation.load(SCENE, overrides={"mesh.nx": 20, "mesh.ny": 2, "time.end": args.end})
    rest = sim.rest_positions
    x = sim.positions  # a view: it follows the steps
    middle = int(np.argmin(np.linalg.norm(rest - [0.0, 0.005, 0.0], axis=1)))
    dt = 0.01
    history = []

    def control(t_next):
        sim.set_motion("right_twist", angle=angle(t_next), axis=(1.0, 0.0, 0.0))

    def record(t):
        history.append((t, angle(t), x[middle, 2]))

    control(dt)
    if args.out:
        # The scene's targets apply at the end of each step: set the next one after every step.
        summary = sim.run(args.out, on_step=lambda info: (record(info.t), control(info.t + dt)))
        print(summary)
    else:
        while sim.time < args.end - dt / 2:
            info = sim.step()
            record(info.t)
            control(info.t + dt)
            if info.step % 10 == 0:
                print(f"t = {info.t:.2f} s  end angle {math.degrees(angle(info.t)):7.1f}°  "
                      f"middle z = {x[middle, 2] * 1e3:+.4f} mm  ({info.newton_iterations} Newton iterations)")

    if args.plot:
        try:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            print("matplotlib is not installed: no plot")
            return
        t, a, z = np.array(history).T
        fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(6, 5))
        ax1.plot(t, np.degrees(a))
        ax1.set_ylabel("end angle [°]")
        ax2.plot(t, z * 1e3)
        ax2.set_ylabel("middle z [mm]")
        ax2.set_xlabel("t [s]")
        fig.tight_layout()
        fig.savefig(args.plot)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
