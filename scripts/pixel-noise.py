#!/usr/bin/env python3
"""Per-pixel noise between seeds, and the time it took: renders SCENE with SEEDS seeds as linear
EXR (not denoised) and prints, for each set of render options, the seconds an image took and the
per-pixel relative noise — each pixel's standard deviation over the seeds over its mean,
summarised by the median and the 90th percentile over the pixels in a region (the whole image,
or its bottom third: the floor in front of the camera) — and that noise scaled to one second,
σ·√t, the figure that equal-time comparisons rank by (lower is better), and to a million rays
traced, σ·√rays, which a loaded machine does not disturb.

Each set of options is one argument of `--variant NAME="OPTIONS"`, e.g.

    python3 scripts/pixel-noise.py examples/peer/black-222.toml --spp 128 --seeds 8 \\
        --variant cache="" --variant full="--no-radiance-cache" [--region floor]
        [--bin target/release/orbifold]

Noise that seeds share (none here: a seed sets every random number of a render) would not show.
Needs a release build and `pip install numpy mitsuba` (Mitsuba reads the EXR files).
"""
import argparse
import json
import os
import shlex
import subprocess
import tempfile

import numpy as np


def load(path):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    image = np.array(mi.Bitmap(path), dtype=np.float64)[..., :3]
    return image @ np.array([0.2126, 0.7152, 0.0722])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--size", default=None)
    parser.add_argument("--region", choices=["all", "floor"], default="all")
    parser.add_argument("--bin", default="target/release/orbifold")
    parser.add_argument("--variant", action="append", default=[],
                        help='NAME="OPTIONS": one set of `orbifold render` options')
    options = parser.parse_args()
    variants = [v.split("=", 1) for v in options.variant] or [["defaults", ""]]
    with tempfile.TemporaryDirectory() as tmp:
        for name, extra in variants:
            images, seconds, rays = [], [], []
            for seed in range(options.seeds):
                out = os.path.join(tmp, f"{name}-{seed}.exr")
                command = [options.bin, "render", options.scene, "--spp", str(options.spp),
                           "--seed", str(seed), "--no-denoise", "--json", "-o", out]
                command += (["--size", options.size] if options.size else []) + shlex.split(extra)
                result = subprocess.run(command, check=True, capture_output=True, text=True)
                summary = json.loads(result.stdout)
                seconds.append(summary["seconds"])
                rays.append(summary["rays"])
                images.append(load(out))
            stack = np.stack(images)
            if options.region == "floor":
                stack = stack[:, 2 * stack.shape[1] // 3:, :]
            mean = stack.mean(axis=0)
            lit = mean > 1e-3 * mean.max()
            relative = stack.std(axis=0, ddof=1)[lit] / mean[lit]
            t, work = float(np.mean(seconds)), float(np.mean(rays)) / 1e6
            median, p90 = np.median(relative), np.percentile(relative, 90)
            print(f"{name:>12}: {t:7.2f} s, {work:.2f} M rays an image; per-pixel noise median "
                  f"{100 * median:.2f} %, 90th percentile {100 * p90:.2f} %; median × √t "
                  f"{100 * median * t ** 0.5:.2f}, × √(M rays) {100 * median * work ** 0.5:.2f}",
                  flush=True)


if __name__ == "__main__":
    main()
