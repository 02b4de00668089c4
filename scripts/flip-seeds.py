#!/usr/bin/env python3
"""A perceptual read of Table 8.1's noise: ꟻLIP between the two seeds' images of each room.

`table81 --save DIR` writes, for every room, the raw and the denoised 8-bit images of two seeds
(`star444-raw.png`, `star444-raw-2.png`, `star444-denoised.png`, `star444-denoised-2.png`).
Table 8.1 measures the noise as the RMS and percentiles of their difference in grey levels.
ꟻLIP (Andersson et al. 2020, "FLIP: A Difference Evaluator for Alternating Images") instead
estimates, per pixel, how different an observer finds the two images when flipping between
them at a given viewing distance (67 pixels per degree by default: a 4K 24" monitor at 70 cm).
It weights colour differences by the eye's contrast sensitivity and differences in edges and
points by what the eye picks out, in [0, 1]. This script prints its mean, median and 99th
percentile for each pair found.

Needs `pip install flip-evaluator numpy pillow` (NVIDIA's reference implementation).

    cargo run --release -p orbifold-render --example table81 -- --size 448 --seconds 30 --save DIR
    python3 scripts/flip-seeds.py DIR [DIR ...] [--ppd 67]
"""
import argparse
import glob
import os

import flip_evaluator as flip
import numpy as np
from PIL import Image


def load(path):
    return np.asarray(Image.open(path).convert("RGB")).astype(np.float32) / 255.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dirs", nargs="+", help="directories written by table81 --save")
    parser.add_argument("--ppd", type=float, default=67.0, help="pixels per degree of view")
    args = parser.parse_args()
    print("| room | image | ꟻLIP mean | median | 99th percentile |")
    print("|---|---|---:|---:|---:|")
    for directory in args.dirs:
        for first in sorted(glob.glob(os.path.join(directory, "*-denoised.png"))):
            room = os.path.basename(first)[: -len("-denoised.png")]
            for kind in ("raw", "denoised"):
                a = os.path.join(directory, f"{room}-{kind}.png")
                b = os.path.join(directory, f"{room}-{kind}-2.png")
                if not (os.path.exists(a) and os.path.exists(b)):
                    continue
                error_map, mean, _ = flip.evaluate(
                    load(a), load(b), "LDR", applyMagma=False, parameters={"ppd": args.ppd}
                )
                print(
                    f"| `{room.replace('star', '*')}` | {kind} | {mean:.4f} | "
                    f"{np.median(error_map):.4f} | {np.quantile(error_map, 0.99):.4f} |"
                )


if __name__ == "__main__":
    main()
