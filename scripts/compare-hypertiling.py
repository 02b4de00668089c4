#!/usr/bin/env python3
"""Side-by-side timing of the {7,4} tiling: hypertiling's generative-reflection kernels against
`orbifold cover '*2222222'`, in one run on one machine.

hypertiling's n layers are our word lengths 0 … n−1 (both give 2 568 763 heptagons for n = 10).
Needs `pip install hypertiling numba` and a release build (`cargo build --release -p orbifold-cli`).

    python3 scripts/compare-hypertiling.py [LAYERS] [REPEATS]
"""
import json
import subprocess
import sys
import time

from hypertiling import HyperbolicTiling

layers = int(sys.argv[1]) if len(sys.argv) > 1 else 10
repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 5
binary = "target/release/orbifold"

results = {}
for kernel in ["GR", "GRC"]:
    HyperbolicTiling(7, 4, 4, kernel=kernel)  # compile the numba kernels first
    best, count = float("inf"), 0
    for _ in range(repeats):
        start = time.perf_counter()
        tiling = HyperbolicTiling(7, 4, layers, kernel=kernel)
        best = min(best, time.perf_counter() - start)
        count = len(tiling)
    results[f"hypertiling {kernel}"] = (count, best)

best, count = float("inf"), 0
for _ in range(repeats):
    out = subprocess.run([binary, "cover", "*2222222", "--depth", str(layers - 1), "--json"],
                         check=True, capture_output=True, text=True).stdout
    report = json.loads(out)
    best = min(best, report["seconds"])
    count = report["total"]
results["orbifold cover"] = (count, best)

reference = max(c / t for name, (c, t) in results.items() if name.startswith("hypertiling"))
for name, (c, t) in results.items():
    rate = c / t
    print(f"{name:18} {c:>10} tiles  {t * 1e3:8.1f} ms  {rate / 1e6:6.2f} M tiles/s  {rate / reference:5.2f}x")
