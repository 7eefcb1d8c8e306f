#!/usr/bin/env python3
"""A stopping rule on the energy's progress, tried after the fact on the
curves of `masssprings converge` (docs/convergence.md, "Stopping rules").

The rule: stop at the first iteration k at which the energy fell, over the
last w iterations, by at most w * T times everything it has fallen since the
step's start:  E(k-w) - E(k) <= w * T * (E(0) - E(k)).

For each scene, T and w it prints, per method, the median over the steps of
the estimated time of a step stopped by the rule, as a fraction of plain-50's
(iterations x the method's cost per iteration relative to plain's, over 50:
the CSV's own elapsed_ms includes the observer's evaluations of the energy
and gradient at every iterate, so it is not used), the median iterations,
and on how many steps the rule stopped at or below plain-50's energy.

Make the curves first (steps 1..30, flag and skirt):

  for s in flag skirt; do for k in $(seq 1 30); do
    masssprings converge data/$s.json --step $k --iterations 60 \\
      --methods plain,chebyshev,anderson,lbfgs --csv DIR/$s-$k.csv
  done; done
  python3 benches/stopping_rules.py DIR [chebyshev=1.09 anderson=1.32 lbfgs=1.94]

The default costs per iteration are those `cargo bench -p
masssprings-benches --bench iteration_cost` measured on the flag.

It also prints, per step, plain-50's decrease over plain's first one
(E(x_0) - E(x_50)) / (E(x_0) - E(x_1)): at most 50 wherever the plain
iteration's decrease does not grow, the premise of `--at-least-plain`
(docs/convergence.md, "A floor from the first plain iteration"); the same
over the sharper bound from two plain decreases, d1 + 49 d2; and which
steps each method ends short of plain-50's energy when the floor 50 d1,
held with the energy rule (T = 0.15), is waived once an iteration lowers
the energy by at most eps of the step's decrease (the "converged" waiver
of docs/convergence.md, "Not done").
"""
import csv
import statistics
import sys

METHODS = ["chebyshev", "anderson", "lbfgs"]


def load(path):
    curves = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            curves.setdefault(row["method"], []).append(float(row["energy"]))
    return curves


def stop_at(energies, tolerance, window):
    for k in range(window, len(energies)):
        if energies[k - window] - energies[k] <= window * tolerance * -energies[k]:
            return k
    return len(energies) - 1


def floor_stop(energies, plain, tolerance, waiver):
    """Where the floor 50 d1 with the energy rule stops, the floor waived
    once the progress is at most `waiver` of the decrease."""
    floor = 50 * plain[1]
    for k in range(1, len(energies)):
        decrease, total = energies[k - 1] - energies[k], -energies[k]
        rule = 0 <= decrease <= tolerance * total
        if rule and (energies[k] <= floor or decrease <= waiver * total):
            return k
    return len(energies) - 1


def main():
    folder = sys.argv[1]
    cost = {"chebyshev": 1.09, "anderson": 1.32, "lbfgs": 1.94}
    for arg in sys.argv[2:]:
        name, value = arg.split("=")
        cost[name] = float(value)
    for scene in ["flag", "skirt"]:
        steps = [load(f"{folder}/{scene}-{k}.csv") for k in range(1, 31)]
        ratios = [c["plain"][50] / c["plain"][1] for c in steps]
        print(f"{scene} plain-50 / first plain decrease: " + " ".join(f"{r:.1f}" for r in ratios))
        sharper = [
            c["plain"][50] / (c["plain"][1] + 49 * (c["plain"][2] - c["plain"][1])) for c in steps
        ]
        print(f"{scene} plain-50 / (d1 + 49 d2): " + " ".join(f"{r:.2f}" for r in sharper))
        for waiver in [1e-3, 1e-2]:
            cells = []
            for method in METHODS:
                short = [
                    k + 1
                    for k, c in enumerate(steps)
                    if c[method][floor_stop(c[method], c["plain"], 0.15, waiver)] > c["plain"][50]
                ]
                cells.append(f"{method} short on {short}")
            print(f"{scene} floor waived below {waiver:g}: " + "  ".join(cells))
        for window in [1, 2, 3]:
            for tolerance in [0.2, 0.1, 0.05, 0.03]:
                cells = []
                for method in METHODS:
                    times, iterations, reached = [], [], 0
                    for curves in steps:
                        plain_50 = curves["plain"][50]
                        energies = curves[method]
                        k = stop_at(energies, tolerance, window)
                        iterations.append(k)
                        times.append(k * cost[method] / 50)
                        reached += energies[k] <= plain_50
                    cells.append(
                        f"{method} {statistics.median(times):.3f}"
                        f" ({statistics.median(iterations):g}) {reached}/30"
                    )
                print(f"{scene} w={window} T={tolerance}: " + "  ".join(cells))


if __name__ == "__main__":
    main()
