#!/usr/bin/env python3
"""Measures the bias of adaptive sampling: the raw image's mean with adaptive sampling on (the
default) against the mean with every pixel sampled alike (`--no-adaptive`), over many seeds.

For each seed it renders SCENE both ways as linear EXR (not denoised) and takes the mean
luminance of each image; it prints, for each sample count, the mean of the relative difference
(adaptive − uniform) / uniform and its standard error over the seeds. Both renders of a seed
share their first samples, so the difference varies less than either image.

    python3 scripts/adaptive-bias.py examples/peer/grey-2222.toml [--spp 8,16,64]
        [--seeds 64] [--size 160x120] [--bin target/release/orbifold] [--args "..."]

Needs a release build (`cargo build --release -p orbifold-cli`) and `pip install numpy
mitsuba` (Mitsuba reads the EXR files).
"""
import argparse
import math
import os
import shlex
import subprocess
import tempfile

import numpy as np


def mean_luminance(path):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    image = np.array(mi.Bitmap(path), dtype=np.float64)[..., :3]
    return float(np.mean(image @ np.array([0.2126, 0.7152, 0.0722])))


def render(binary, scene, spp, seed, size, adaptive, extra, out):
    command = [binary, "render", scene, "--spp", str(spp), "--seed", str(seed), "--size", size,
               "--no-denoise", "-o", out] + ([] if adaptive else ["--no-adaptive"]) + extra
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return mean_luminance(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--spp", default="8,16,64")
    parser.add_argument("--seeds", type=int, default=64)
    parser.add_argument("--size", default="160x120")
    parser.add_argument("--bin", default="target/release/orbifold")
    parser.add_argument("--args", default="", help="more options for `orbifold render`")
    options = parser.parse_args()
    extra = shlex.split(options.args)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "image.exr")
        for spp in [int(s) for s in options.spp.split(",")]:
            differences = []
            for seed in range(options.seeds):
                uniform = render(options.bin, options.scene, spp, seed, options.size, False,
                                 extra, out)
                adaptive = render(options.bin, options.scene, spp, seed, options.size, True,
                                  extra, out)
                differences.append((adaptive - uniform) / uniform)
            mean = float(np.mean(differences))
            error = float(np.std(differences, ddof=1)) / math.sqrt(len(differences))
            print(f"{spp:5d} spp: adaptive − uniform = {100 * mean:+.3f} ± {100 * error:.3f} % "
                  f"({mean / error:+.1f} standard errors, {len(differences)} seeds)", flush=True)


if __name__ == "__main__":
    main()
