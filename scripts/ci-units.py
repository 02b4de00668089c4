#!/usr/bin/env python3
"""How much a second cargo command builds again after a first one, without building anything.

    scripts/ci-units.py "test --workspace --no-run" "build -p orbifold-studio"

Reads both commands' unit graphs (`cargo ... --unit-graph`, an unstable flag that stable cargo
gives with RUSTC_BOOTSTRAP=1) and counts the second's units that the first did not build: a unit
is the same build only if its package, target, mode, features and profile are the same and so
are all its dependencies, as in cargo's own file names (a crate built over a different serde is
built again). Prints the count and the packages (docs/ci.md).
"""
import json
import os
import subprocess
import sys


def graph(command):
    env = dict(os.environ, RUSTC_BOOTSTRAP="1")
    out = subprocess.run(
        ["cargo", *command.split(), "--locked", "--unit-graph", "-Z", "unstable-options"],
        check=True, capture_output=True, text=True, env=env,
    ).stdout
    return json.loads(out)["units"]


def identities(units):
    """Each unit's identity: its own settings and its dependencies' identities."""
    memo = {}

    def ident(i):
        if i not in memo:
            u = units[i]
            p = u["profile"]
            own = (u["pkg_id"], u["target"]["name"], tuple(u["target"]["kind"]), u["mode"],
                   tuple(sorted(u["features"])), p["opt_level"], str(p.get("debuginfo")),
                   u.get("platform"))
            memo[i] = hash((own, tuple(sorted(ident(d["index"]) for d in u["dependencies"]))))
        return memo[i]

    return [ident(i) for i in range(len(units))]


def name(pkg_id):
    # "registry+https://...#wgpu@30.0.1" or "path+file:///.../crates/orbifold-scene#0.1.0"
    tail = pkg_id.rsplit("#", 1)
    if "@" in tail[-1]:
        return tail[-1].split("@")[0]
    return tail[0].rstrip("/").rsplit("/", 1)[-1]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    first, second = graph(sys.argv[1]), graph(sys.argv[2])
    built = set(identities(first))
    ids = identities(second)
    again = [u for u, i in zip(second, ids) if i not in built]
    print(f"{len(second)} units, {len(again)} built again")
    print(" ".join(sorted({name(u["pkg_id"]) for u in again})))


if __name__ == "__main__":
    main()
