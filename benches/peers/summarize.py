#!/usr/bin/env python3
"""Summarise compare.sh's results.jsonl: medians over rounds, and ratios.

Each line of the input is one measurement: {"round", "matrix", "tool",
"data"}, where tool is ours (masssprings analyze --json), cholmod
(cholmod_peer --json), faer (faer_peer --json), ours-step (masssprings simulate --json) or eigen
(eigen-ref bench, its CSV line); ours-threads, faer-threads and
ours-step-threads are the same on several threads (compare.sh's THREADS).
Prints Markdown tables.
"""
import json
import statistics
import sys
from collections import defaultdict

# eigen-ref bench's CSV line: CSV,name,n,springs,nnzQl,nnzL,build,analyze,
# factorize,solve,local,assembly,step,GB/s,steps
EIGEN_FIELDS = {"nnz_l": 5, "analyze_s": 7, "numeric_s": 8, "solve_s": 9, "step_s": 12}


def load(path):
    values = defaultdict(list)  # (matrix, tool, key) -> [value per round]
    order = []
    for line in open(path):
        record = json.loads(line)
        matrix, tool, data = record["matrix"], record["tool"], record["data"]
        if matrix not in order:
            order.append(matrix)
        if tool == "eigen":
            fields = data["csv"].split(",")
            data = {key: float(fields[i]) for key, i in EIGEN_FIELDS.items()}
        for key, value in data.items():
            if isinstance(value, (int, float)):
                values[(matrix, tool, key)].append(float(value))
    return values, order


def median(values, matrix, tool, key):
    samples = values.get((matrix, tool, key))
    return statistics.median(samples) if samples else float("nan")


def ms(seconds):
    return f"{seconds * 1e3:.3f}"


def main():
    values, order = load(sys.argv[1])
    m = lambda matrix, tool, key: median(values, matrix, tool, key)
    rounds = max(len(v) for v in values.values())
    print(f"Medians over {rounds} rounds; times in ms; ratio = ours / peer.\n")

    print("| matrix | nnz(L) ours | SuiteSparse AMD | Eigen | ordering ours | SuiteSparse AMD | ratio |")
    print("|---|---|---|---|---|---|---|")
    for x in order:
        ours, ss = m(x, "ours", "ordering_s"), m(x, "cholmod", "amd_s")
        print(f"| {x} | {m(x, 'ours', 'nnz_l'):,.0f} | {m(x, 'cholmod', 'amd_nnz_l'):,.0f} | "
              f"{m(x, 'eigen', 'nnz_l'):,.0f} | {ms(ours)} | {ms(ss)} | {ours / ss:.2f} |")

    print("\n| matrix | solve ours | CHOLMOD simplicial | ratio | Eigen | ratio | residual |")
    print("|---|---|---|---|---|---|---|")
    for x in order:
        ours, ch, ei = m(x, "ours", "solve_s"), m(x, "cholmod", "simplicial_solve_s"), m(x, "eigen", "solve_s")
        print(f"| {x} | {ms(ours)} | {ms(ch)} | {ours / ch:.2f} | {ms(ei)} | {ours / ei:.2f} | "
              f"{m(x, 'ours', 'residual'):.1e} |")

    print("\n| matrix | numeric ours (supernodal) | Eigen | ratio | CHOLMOD simplicial | CHOLMOD supernodal | ratio |")
    print("|---|---|---|---|---|---|---|")
    for x in order:
        ours, ei = m(x, "ours", "numeric_s"), m(x, "eigen", "numeric_s")
        cs, cn = m(x, "cholmod", "simplicial_numeric_s"), m(x, "cholmod", "supernodal_numeric_s")
        print(f"| {x} | {ms(ours)} | {ms(ei)} | {ours / ei:.2f} | {ms(cs)} | {ms(cn)} | {ours / cn:.2f} |")

    if any(tool == "faer" for (_, tool, _) in values):
        print("\n| matrix | numeric ours | faer supernodal | ratio (target ≤ 0.85, grid-1000 ≤ 1.0) "
              "| solve ours | faer simplicial | faer supernodal | best peer (faer, CHOLMOD) | ratio (target ≤ 0.8) |")
        print("|---|---|---|---|---|---|---|---|---|")
        for x in order:
            ours_n, faer_n = m(x, "ours", "numeric_s"), m(x, "faer", "supernodal_numeric_s")
            ours_s = m(x, "ours", "solve_s")
            peers = [m(x, "faer", "simplicial_solve_s"), m(x, "faer", "supernodal_solve_s"),
                     m(x, "cholmod", "simplicial_solve_s"), m(x, "cholmod", "supernodal_solve_s")]
            best = min(p for p in peers if p == p)
            print(f"| {x} | {ms(ours_n)} | {ms(faer_n)} | {ours_n / faer_n:.2f} | {ms(ours_s)} | "
                  f"{ms(peers[0])} | {ms(peers[1])} | {ms(best)} | {ours_s / best:.2f} |")

    if any(tool == "faer" for (_, tool, _) in values):
        symbolic_table(m, order)

    if any(tool == "ours-threads" for (_, tool, _) in values):
        threads_table(m, order)

    print("\n| scene | step ours (50 iterations) | Eigen (the assignment's solver) | ratio |")
    print("|---|---|---|---|")
    for x in order:
        ours, ei = m(x, "ours-step", "step_median_s"), m(x, "eigen", "step_s")
        print(f"| {x} | {ms(ours)} | {ms(ei)} | {ours / ei:.2f} |")


def threads_table(m, order):
    """Ours on several threads over ours on one (the same bits), and beside
    faer on as many threads."""
    threads = next((m(x, "ours-threads", "threads") for x in order), float("nan"))
    header = ["matrix", "numeric 1t", f"numeric {threads:.0f}t", "speedup (target ≥ 1.6)",
              f"faer supernodal {threads:.0f}t", "ours / faer (target ≤ 0.9)",
              "solve 1t", f"solve {threads:.0f}t", "speedup",
              "step 1t", f"step {threads:.0f}t", "speedup (grid-316 ≥ 1.5, skirt ≥ 1.3, flag ≥ 1)"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for x in order:
        n1, nt = m(x, "ours", "numeric_s"), m(x, "ours-threads", "numeric_s")
        faer_t = m(x, "faer-threads", "supernodal_numeric_s")
        s1, st = m(x, "ours", "solve_s"), m(x, "ours-threads", "solve_s")
        p1, pt = m(x, "ours-step", "step_median_s"), m(x, "ours-step-threads", "step_median_s")
        cells = [x, ms(n1), ms(nt), f"{n1 / nt:.2f}", ms(faer_t), f"{nt / faer_t:.2f}",
                 ms(s1), ms(st), f"{s1 / st:.2f}", ms(p1), ms(pt), f"{p1 / pt:.2f}"]
        lines.append("| " + " | ".join(cells) + " |")
    print("\n" + "\n".join(lines))


def symbolic_table(m, order):
    """Our symbolic analysis beside our numeric factorization and faer's
    symbolic phase, which computes its AMD ordering inside (ours is timed
    apart, so the sum is shown too)."""
    header = ["matrix", "symbolic ours", "numeric ours", "ratio (target ≤ 0.5)",
              "faer symbolic (AMD included)", "ours / faer (target ≤ 1)", "ours with ordering / faer"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for x in order:
        sym, num = m(x, "ours", "symbolic_s"), m(x, "ours", "numeric_s")
        ordering, faer_s = m(x, "ours", "ordering_s"), m(x, "faer", "supernodal_symbolic_s")
        cells = [x, ms(sym), ms(num), f"{sym / num:.2f}", ms(faer_s),
                 f"{sym / faer_s:.2f}", f"{(ordering + sym) / faer_s:.2f}"]
        lines.append("| " + " | ".join(cells) + " |")
    print("\n" + "\n".join(lines))


if __name__ == "__main__":
    main()
