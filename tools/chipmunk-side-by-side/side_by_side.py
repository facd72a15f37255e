#!/usr/bin/env python3
"""Runs a Tamias2D scene file (`tamias scene dump NAME`) through Chipmunk2D
(Munk2D, the fork of Chipmunk2D that pymunk bundles as a C library) and, with `--ours`, through `tamias run`:
each engine's median time per step on one thread, and the deepest overlap.

Chipmunk is the engine our sequential solver follows (the same settings:
iterations, slop, bias, persistence, damping; frictions and elasticities
multiplied), so the two run the same scene file at the same settings.
Only `Space.step` (one call into C) is timed; building and spawning are not.

    python side_by_side.py scene.json [--steps N] [--no-sleep] [--json] [--ours TAMIAS]
    python side_by_side.py --table results.jsonl
"""
import argparse
import json
import math
import re
import statistics
import subprocess
import sys
import time
from importlib.metadata import version

import pymunk


def num(s):
    return float(s)


def vec(v):
    return (num(v[0]), num(v[1])) if v is not None else (0.0, 0.0)


def add_shape(body, s):
    g = s["geometry"]
    kind = g["kind"]
    radius = num(g.get("radius", "0"))
    if kind == "circle":
        shape = pymunk.Circle(body, radius, vec(g.get("offset")))
    elif kind == "segment":
        shape = pymunk.Segment(body, vec(g["a"]), vec(g["b"]), radius)
    elif kind == "box":
        hx, hy = num(g["width"]) / 2, num(g["height"]) / 2
        ox, oy = vec(g.get("offset"))
        verts = [(ox - hx, oy - hy), (ox + hx, oy - hy), (ox + hx, oy + hy), (ox - hx, oy + hy)]
        shape = pymunk.Poly(body, verts, radius=radius)
    elif kind in ("poly", "raw_poly"):
        shape = pymunk.Poly(body, [vec(p) for p in g["verts"]], radius=radius)
    else:
        raise SystemExit(f"unknown geometry {kind}")
    shape.friction = num(s.get("friction", "0"))
    shape.elasticity = num(s.get("elasticity", "0"))
    shape.sensor = bool(s.get("sensor", False))
    mass = s.get("mass", "none")
    if isinstance(mass, dict) and "density" in mass:
        shape.density = num(mass["density"])
    elif isinstance(mass, dict) and "mass" in mass:
        shape.mass = num(mass["mass"])
    f = s.get("filter")
    if f:
        shape.filter = pymunk.ShapeFilter(group=f["group"], categories=f["categories"],
                                          mask=f["mask"])
    return shape


BODY_TYPE = {"static": pymunk.Body.STATIC, "kinematic": pymunk.Body.KINEMATIC,
             "dynamic": pymunk.Body.DYNAMIC}


def add_body(space, b):
    m = b.get("mass", "from_shapes")
    if b["kind"] == "dynamic" and isinstance(m, dict) and "explicit" in m:
        body = pymunk.Body(num(m["explicit"]["mass"]), num(m["explicit"]["moment"]))
    else:
        body = pymunk.Body(body_type=BODY_TYPE[b["kind"]])
    body.position = vec(b.get("position"))
    body.angle = num(b.get("angle", "0"))
    shapes = [add_shape(body, s) for s in b["shapes"]]
    space.add(body, *shapes)
    if b["kind"] != "static":
        body.velocity = vec(b.get("velocity"))
        body.angular_velocity = num(b.get("angular_velocity", "0"))
    return body


def deepest(space):
    """The deepest contact of the touching pairs (Chipmunk's `distance`)."""
    worst = 0.0
    for body in space.bodies:
        if body.body_type != pymunk.Body.DYNAMIC:
            continue

        def each(arb):
            nonlocal worst
            for p in arb.contact_point_set.points:
                worst = min(worst, p.distance)

        body.each_arbiter(each)
    return -worst


def run(desc, steps, sleep, every):
    if desc.get("constraints"):
        raise SystemExit(f"{desc['name']}: joints are not mapped (bodies and shapes only)")
    s = desc.get("settings", {})
    space = pymunk.Space()
    space.gravity = vec(s.get("gravity", ["0", "0"]))
    space.iterations = int(s.get("iterations", 10))
    space.damping = num(s.get("damping", "1"))
    space.collision_slop = num(s.get("collision_slop", "0.1"))
    space.collision_bias = num(s.get("collision_bias", "0.00179701"))
    space.collision_persistence = int(s.get("collision_persistence", 3))
    if sleep and "sleep_time_threshold" in s and num(s["sleep_time_threshold"]) < 1e6:
        space.sleep_time_threshold = num(s["sleep_time_threshold"])
    if "idle_speed_threshold" in s:
        space.idle_speed_threshold = num(s["idle_speed_threshold"])
    for b in desc["bodies"]:
        add_body(space, b)
    spawns = {}
    for sp in desc.get("spawns", []):
        spawns.setdefault(sp["at_step"], []).extend(sp["bodies"])
    dt = num(desc["dt"])
    times, pen = [], 0.0
    for step in range(steps):
        for b in spawns.get(step, []):
            add_body(space, b)
        t0 = time.perf_counter()
        space.step(dt)
        times.append(time.perf_counter() - t0)
        if (step + 1) % every == 0 or step + 1 == steps:
            pen = max(pen, deepest(space))
    return {
        "scene": desc["name"],
        "engine": f"Munk2D {pymunk.chipmunk_version.split('-')[0]}, the Chipmunk2D fork of pymunk "
                  f"{version('pymunk')}",
        "bodies": len(space.bodies),
        "steps": steps,
        "median_ms": statistics.median(times) * 1e3 if times else 0.0,
        "mean_ms": statistics.fmean(times) * 1e3 if times else 0.0,
        "max_penetration": pen,
    }


def run_ours(tamias, scene, steps, solver=None):
    """`tamias run SCENE --trusted --threads 1 [--solver KIND]`: its figures."""
    cmd = [tamias, "run", scene, "--trusted", "--threads", "1", "--steps", str(steps)]
    if solver:
        cmd += ["--solver", solver]
    text = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    out = {}
    m = re.search(r"time per step: median ([0-9.]+) ms", text)
    if m:
        out["median_ms"] = float(m.group(1))
    m = re.search(r"^max penetration: ([-0-9.e]+)", text, re.M)
    if m:
        out["max_penetration"] = float(m.group(1))
    return out


def table(path):
    rows = [json.loads(line) for line in open(path) if line.strip()]
    if rows:
        print(f"Chipmunk: {rows[0]['engine']}; both on one thread\n")
    print("| scene | Chipmunk ms/step | ours ms/step | ours ÷ Chipmunk "
          "| max penetration Chipmunk / ours |")
    print("|---|---:|---:|---:|---:|")
    for r in rows:
        o = r.get("ours", {})
        ratio = o["median_ms"] / r["median_ms"] if r["median_ms"] > 0 and "median_ms" in o else math.nan
        print(f"| {r['scene']} | {r['median_ms']:.3f} | {o.get('median_ms', math.nan):.3f} "
              f"| {ratio:.2f} | {r['max_penetration']:.3g} / {o.get('max_penetration', math.nan):.3g} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", nargs="?", help="a scene file from `tamias scene dump`")
    ap.add_argument("--steps", type=int, help="steps [the scene's]")
    ap.add_argument("--no-sleep", action="store_true", help="sleeping off in both engines")
    ap.add_argument("--every", type=int, default=10, help="measure the overlap every K steps [10]")
    ap.add_argument("--json", action="store_true", help="one JSON object instead of lines")
    ap.add_argument("--ours", metavar="TAMIAS", help="also run `TAMIAS run SCENE --threads 1`")
    ap.add_argument("--solver", choices=["sequential", "soft", "soft-narrow"],
                    help="our solver (`tamias run --solver`) [default: the scene's]")
    ap.add_argument("--table", metavar="JSONL", help="print the markdown table of --json lines")
    args = ap.parse_args()
    if args.table:
        return table(args.table)
    with open(args.scene) as f:
        desc = json.load(f)
    if args.no_sleep:  # ours: an island never rests this long
        desc.setdefault("settings", {})["sleep_time_threshold"] = "1000000"
    steps = args.steps if args.steps is not None else desc["steps"]
    r = run(desc, steps, not args.no_sleep, max(1, args.every))
    if args.ours:
        scene = args.scene
        if args.no_sleep:
            scene = args.scene.removesuffix(".json") + ".awake.json"
            with open(scene, "w") as f:
                json.dump(desc, f)
        r["ours"] = run_ours(args.ours, scene, steps, args.solver)
    if args.json:
        print(json.dumps(r))
    else:
        for k, v in r.items():
            print(f"{k.replace('_', ' ')}: {v}")


if __name__ == "__main__":
    sys.exit(main())
