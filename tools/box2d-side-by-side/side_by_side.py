#!/usr/bin/env python3
"""Runs a Tamias2D scene file (`tamias scene dump NAME`) through Box2D v3 and
prints Box2D's time per step and quality figures in the `key: value` shape of
`tamias run`. The mapping of our concepts to Box2D's is in README.md.

Box2D comes from the `box2d-python` package (CFFI bindings of the whole
Box2D 3.1 C API): contact manifolds and mass data are read straight from C.
Only `b2World_Step` is timed; building, spawning and measuring are not.

    python side_by_side.py scene.json [--steps N] [--substeps 4] [--json]
    python side_by_side.py scene.json --ours path/to/tamias   # both engines
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

from box2d._box2d import ffi, lib

HUGE = 1e9  # "unbounded" for Box2D limits (its own b2_huge is 1e5 * units)
PIXEL_PREFIXES = ("bowl_", "bouncy_", "no_collide")  # section A: 10 units/m
STACKING_PREFIXES = ("pyramid_", "many_pyramids_", "stack_")


def num(s):
    return float(s)


def vec(v):
    return (num(v[0]), num(v[1])) if v is not None else (0.0, 0.0)


def b2vec(p):
    return ffi.new("b2Vec2*", {"x": p[0], "y": p[1]})[0]


def rot(angle):
    return {"c": math.cos(angle), "s": math.sin(angle)}


def to_world(p, angle, local):
    c, s = math.cos(angle), math.sin(angle)
    return (p[0] + c * local[0] - s * local[1], p[1] + s * local[0] + c * local[1])


def to_local(p, angle, w):
    c, s = math.cos(angle), math.sin(angle)
    dx, dy = w[0] - p[0], w[1] - p[1]
    return (c * dx + s * dy, -s * dx + c * dy)


def dist(a, b):
    return math.hypot(a[0] - b[0], a[1] - b[1])


# ---------------------------------------------------------------- shapes


def make_geometry(g):
    """(kind, cdata) of the Box2D shape for one of our geometries."""
    kind = g["kind"]
    radius = num(g.get("radius", "0"))
    if kind == "circle":
        return "circle", ffi.new("b2Circle*", {"center": vec(g.get("offset")), "radius": radius})
    if kind == "segment":
        a, b = vec(g["a"]), vec(g["b"])
        if radius > 0:
            return "capsule", ffi.new("b2Capsule*", {"center1": a, "center2": b, "radius": radius})
        return "segment", ffi.new("b2Segment*", {"point1": a, "point2": b})
    if kind == "box":
        hx, hy = num(g["width"]) / 2, num(g["height"]) / 2
        poly = lib.b2MakeOffsetRoundedBox(hx, hy, b2vec(vec(g.get("offset"))), rot(0), radius)
        return "polygon", ffi.new("b2Polygon*", poly)
    if kind in ("poly", "raw_poly"):
        pts = [vec(p) for p in g["verts"]]
        if len(pts) > 8:
            raise SystemExit(f"a polygon of {len(pts)} points: Box2D takes at most 8")
        hull = lib.b2ComputeHull(ffi.new("b2Vec2[]", pts), len(pts))
        if hull.count == 0:
            raise SystemExit("Box2D rejects a polygon's hull")
        return "polygon", ffi.new("b2Polygon*", lib.b2MakePolygon(ffi.new("b2Hull*", hull), radius))
    raise SystemExit(f"unknown geometry {kind}")


AREA = {
    "circle": lib.b2ComputeCircleMass,
    "capsule": lib.b2ComputeCapsuleMass,
    "polygon": lib.b2ComputePolygonMass,
}
CREATE = {
    "circle": lib.b2CreateCircleShape,
    "capsule": lib.b2CreateCapsuleShape,
    "polygon": lib.b2CreatePolygonShape,
    "segment": lib.b2CreateSegmentShape,
}


def add_shape(body, s):
    kind, geom = make_geometry(s["geometry"])
    d = lib.b2DefaultShapeDef()
    # Ours multiplies the two frictions, Box2D takes sqrt(fa * fb): squared
    # frictions give Box2D exactly our product.
    d.friction = num(s.get("friction", "0")) ** 2
    d.restitution = num(s.get("elasticity", "0"))
    d.isSensor = bool(s.get("sensor", False))
    d.updateBodyMass = False
    d.density = 0.0
    mass = s.get("mass", "none")
    if isinstance(mass, dict) and "density" in mass:
        d.density = num(mass["density"])
    elif isinstance(mass, dict) and "mass" in mass:
        area = AREA[kind](geom, 1.0).mass if kind in AREA else 0.0
        d.density = num(mass["mass"]) / area if area > 0 else 0.0
    f = s.get("filter")
    if f:
        d.filter.categoryBits = f["categories"]
        d.filter.maskBits = f["mask"]
        d.filter.groupIndex = -f["group"]
    CREATE[kind](body, ffi.new("b2ShapeDef*", d), geom)


BODY_TYPE = {"static": lib.b2_staticBody, "kinematic": lib.b2_kinematicBody, "dynamic": lib.b2_dynamicBody}


def add_body(world, b, damping):
    d = lib.b2DefaultBodyDef()
    d.type = BODY_TYPE[b["kind"]]
    # Our body position is the body origin (shapes and anchors are relative to
    # it; the centre of gravity follows from the shapes), as Box2D's is.
    d.position = vec(b.get("position"))
    d.rotation = rot(num(b.get("angle", "0")))
    d.linearVelocity = vec(b.get("velocity"))
    d.angularVelocity = num(b.get("angular_velocity", "0"))
    d.linearDamping = d.angularDamping = damping
    d.isBullet = bool(b.get("bullet", False))
    body = lib.b2CreateBody(world, ffi.new("b2BodyDef*", d))
    for s in b["shapes"]:
        add_shape(body, s)
    m = b.get("mass", "from_shapes")
    if b["kind"] == "dynamic" and isinstance(m, dict):
        md = {"mass": num(m["explicit"]["mass"]), "center": (0, 0),
              "rotationalInertia": num(m["explicit"]["moment"])}
        lib.b2Body_SetMassData(body, ffi.new("b2MassData*", md)[0])
    else:
        lib.b2Body_ApplyMassFromShapes(body)
    return body


# ---------------------------------------------------------------- joints


def resolve(desc):
    """Our constraints with their anchors worked out as our build does (a
    pivot's world point to both bodies, a pin's length measured)."""
    pose = [(vec(b.get("position")), num(b.get("angle", "0"))) for b in desc["bodies"]]
    out = []
    for c in desc.get("constraints", []):
        (pa, aa), (pb, ab) = pose[c["a"]], pose[c["b"]]
        if "pivot" in c:
            w = vec(c["pivot"])
            anchor_a, anchor_b = to_local(pa, aa, w), to_local(pb, ab, w)
        else:
            anchor_a, anchor_b = vec(c.get("anchor_a")), vec(c.get("anchor_b"))
        measured = dist(to_world(pa, aa, anchor_a), to_world(pb, ab, anchor_b))
        r = dict(c, anchor_a=anchor_a, anchor_b=anchor_b)
        for k in ("dist", "min", "max", "rest_length", "rest_angle", "stiffness",
                  "damping", "rate", "max_force"):
            if k in c:
                r[k] = num(c[k])
        r.setdefault("dist", measured)
        r["collide"] = c.get("collide_bodies", True)
        out.append(r)
    return out


def effective(values):
    """1 / (1/a + 1/b), a zero (static or kinematic) side counting as infinite."""
    inv = sum(1 / v for v in values if v > 0)
    return 1 / inv if inv > 0 else 0.0


def spring(k, c, m):
    """Box2D's (hertz, damping ratio) of the spring k, c on effective mass m."""
    if k <= 0 or m <= 0:
        return 0.0, 0.0
    return math.sqrt(k / m) / (2 * math.pi), c / (2 * math.sqrt(k * m))


def build_joints(world, bodies, joints):
    """Creates the Box2D joints; returns the names of those left out.
    A pivot takes the rotary limit, simple motor and rotary spring of the
    same pair into one revolute joint; a groove (a wheel joint) takes the
    simple motor of its pair."""
    pair = lambda j: (j["a"], j["b"])
    hosts = {pair(j): j for j in joints if j["type"] in ("pivot", "groove")}
    left_out = []
    for j in joints:
        t, host = j["type"], hosts.get(pair(j))
        if t in ("rotary_limit", "simple_motor", "damped_rotary_spring"):
            if host is None or (host["type"] == "groove" and t != "simple_motor"):
                left_out.append(j)
            else:
                host.setdefault("extras", []).append(j)
                host["collide"] = host["collide"] and j["collide"]
        elif t in ("gear", "ratchet"):
            left_out.append(j)
    for j in left_out:  # a left-out joint still keeps its bodies apart
        if not j["collide"]:
            d = lib.b2DefaultNullJointDef()
            d.bodyIdA, d.bodyIdB = bodies[j["a"]], bodies[j["b"]]
            lib.b2CreateNullJoint(world, ffi.new("b2NullJointDef*", d))
    mass = lambda i: lib.b2Body_GetMass(bodies[i])
    inertia = lambda i: lib.b2Body_GetRotationalInertia(bodies[i])
    for j in joints:
        a, b, t = bodies[j["a"]], bodies[j["b"]], j["type"]
        if t == "pivot":
            d = lib.b2DefaultRevoluteJointDef()
            for e in j.get("extras", []):
                if e["type"] == "damped_rotary_spring":
                    d.enableSpring = True
                    d.referenceAngle = e["rest_angle"]
                    d.hertz, d.dampingRatio = spring(
                        e["stiffness"], e["damping"], effective([inertia(j["a"]), inertia(j["b"])]))
            for e in j.get("extras", []):
                if e["type"] == "rotary_limit":
                    d.enableLimit = True
                    d.lowerAngle = e["min"] - d.referenceAngle
                    d.upperAngle = e["max"] - d.referenceAngle
                elif e["type"] == "simple_motor":
                    d.enableMotor = True
                    d.motorSpeed = -e["rate"]  # ours: w_b - w_a = -rate
                    d.maxMotorTorque = e.get("max_force", HUGE)
            create = lib.b2CreateRevoluteJoint
        elif t == "groove":
            g0, g1 = vec(j["groove_a"]), vec(j["groove_b"])
            length = dist(g0, g1)
            d = lib.b2DefaultWheelJointDef()
            d.localAxisA = ((g1[0] - g0[0]) / length, (g1[1] - g0[1]) / length)
            j["anchor_a"] = g0
            d.enableSpring = False
            d.enableLimit = True
            d.lowerTranslation, d.upperTranslation = 0.0, length
            for e in j.get("extras", []):
                d.enableMotor = True
                d.motorSpeed = -e["rate"]
                d.maxMotorTorque = e.get("max_force", HUGE)
            create = lib.b2CreateWheelJoint
        elif t in ("pin", "slide", "damped_spring"):
            d = lib.b2DefaultDistanceJointDef()
            if t == "pin":
                d.length = j["dist"]
            elif t == "slide":  # a rope: a spring of 0 Hz between the limits
                d.length = j["max"]
                d.enableSpring, d.hertz = True, 0.0
                d.enableLimit, d.minLength, d.maxLength = True, j["min"], j["max"]
            else:
                d.length = j["rest_length"]
                d.enableSpring = True
                d.hertz, d.dampingRatio = spring(
                    j["stiffness"], j["damping"], effective([mass(j["a"]), mass(j["b"])]))
            create = lib.b2CreateDistanceJoint
        else:
            continue
        d.bodyIdA, d.bodyIdB = a, b
        d.localAnchorA, d.localAnchorB = j["anchor_a"], j["anchor_b"]
        d.collideConnected = j["collide"]
        create(world, ffi.new(ffi.typeof(d).cname + "*", d))
    return [j["type"] for j in left_out]


# ---------------------------------------------------------------- measures


def pose(body):
    p, q = lib.b2Body_GetPosition(body), lib.b2Body_GetRotation(body)
    return (p.x, p.y), math.atan2(q.s, q.c)


def joint_errors(bodies, joints):
    """(positional error, pivot error, rotary-limit error) of this moment,
    as scenes/src/bench/joints.rs measures ours."""
    pos = piv = ang = 0.0
    for j in joints:
        (pa, aa), (pb, ab) = pose(bodies[j["a"]]), pose(bodies[j["b"]])
        wa, wb = to_world(pa, aa, j["anchor_a"]), to_world(pb, ab, j["anchor_b"])
        t = j["type"]
        if t == "pivot":
            e = dist(wa, wb)
            piv = max(piv, e)
        elif t == "pin":
            e = abs(dist(wa, wb) - j["dist"])
        elif t == "slide":
            d = dist(wa, wb)
            e = max(d - j["max"], j["min"] - d, 0.0)
        elif t == "groove":
            g0 = to_world(pa, aa, vec(j["groove_a"]))
            g1 = to_world(pa, aa, vec(j["groove_b"]))
            dx, dy = g1[0] - g0[0], g1[1] - g0[1]
            u = ((wb[0] - g0[0]) * dx + (wb[1] - g0[1]) * dy) / (dx * dx + dy * dy)
            u = min(max(u, 0.0), 1.0)
            e = dist(wb, (g0[0] + u * dx, g0[1] + u * dy))
        elif t == "rotary_limit":
            rel = (ab - aa + math.pi) % (2 * math.pi) - math.pi
            ang = max(ang, rel - j["max"], j["min"] - rel, 0.0)
            continue
        else:
            continue
        pos = max(pos, e)
    return pos, piv, ang


class Contacts:
    """The most negative manifold separation over the bodies' touching
    contacts (manifolds are computed at the start of Box2D's step)."""

    def __init__(self):
        self.cap = 64
        self.buf = ffi.new("b2ContactData[]", self.cap)

    def deepest(self, bodies):
        worst = 0.0
        for body in bodies:
            n = lib.b2Body_GetContactCapacity(body)
            if n == 0:
                continue
            if n > self.cap:
                self.cap, self.buf = n, ffi.new("b2ContactData[]", n)
            for k in range(lib.b2Body_GetContactData(body, self.buf, self.cap)):
                m = self.buf[k].manifold
                for i in range(m.pointCount):
                    worst = min(worst, m.points[i].separation)
        return -worst


# ---------------------------------------------------------------- the run


@ffi.callback("float(float, int, float, int)")
def product(a, _ma, b, _mb):
    return a * b


def run(desc, steps, substeps, sleep, every):
    name = desc["name"]
    units = 10.0 if name.startswith(PIXEL_PREFIXES) else 1.0
    lib.b2SetLengthUnitsPerMeter(units)
    settings = desc.get("settings", {})
    wd = lib.b2DefaultWorldDef()
    wd.gravity = vec(settings.get("gravity", ["0", "0"]))
    wd.enableSleep = sleep
    wd.workerCount = 1  # no task system: Box2D runs on the calling thread
    all_bodies = desc["bodies"] + [b for s in desc.get("spawns", []) for b in s["bodies"]]
    if any(num(s.get("elasticity", "0")) > 0 for b in all_bodies for s in b["shapes"]):
        wd.restitutionCallback = product  # ours multiplies, Box2D takes the max
    world = lib.b2CreateWorld(ffi.new("b2WorldDef*", wd))
    kept = num(settings.get("damping", "1"))
    damping = -math.log(kept) if 0 < kept < 1 else 0.0
    bodies = [add_body(world, b, damping) for b in desc["bodies"]]
    joints = resolve(desc)
    left_out = build_joints(world, bodies, joints)
    spawns = {}
    for s in desc.get("spawns", []):
        spawns.setdefault(s["at_step"], []).extend(s["bodies"])
    forces = [(bodies[f["body"]], vec(f.get("force")), num(f.get("torque", "0")))
              for f in desc.get("forces", [])]
    dynamic = [bodies[i] for i, b in enumerate(desc["bodies"]) if b["kind"] == "dynamic"]
    dt = num(desc["dt"])
    contacts = Contacts()
    times, pen, pos, piv, ang = [], 0.0, 0.0, 0.0, 0.0
    for step in range(steps):
        for b in spawns.get(step, []):
            body = add_body(world, b, damping)
            if b["kind"] == "dynamic":
                dynamic.append(body)
        for body, f, t in forces:
            lib.b2Body_ApplyForceToCenter(body, f, True)
            lib.b2Body_ApplyTorque(body, t, True)
        t0 = time.perf_counter()
        lib.b2World_Step(world, dt, substeps)
        times.append(time.perf_counter() - t0)
        if (step + 1) % every == 0 or step + 1 == steps:
            pen = max(pen, contacts.deepest(dynamic))
            e = joint_errors(bodies, joints)
            pos, piv, ang = max(pos, e[0]), max(piv, e[1]), max(ang, e[2])
    v = lib.b2GetVersion()
    out = {
        "scene": name,
        "engine": f"Box2D {v.major}.{v.minor}.{v.revision} (box2d-python {version('box2d-python')})",
        "bodies": len(bodies) + sum(len(b) for b in spawns.values()),
        "steps": steps, "substeps": substeps, "threads": 1, "length_units_per_metre": units,
        "median_ms": statistics.median(times) * 1e3 if times else 0.0,
        "mean_ms": statistics.fmean(times) * 1e3 if times else 0.0,
        "total_s": sum(times),
        "max_penetration": pen,
        "sleeping_bodies": len(dynamic) - lib.b2World_GetAwakeBodyCount(world),
    }
    kinds = {j["type"] for j in joints}
    if kinds & {"pivot", "pin", "slide", "groove"}:
        out["max_joint_error"] = pos
    if "rotary_limit" in kinds:
        out["max_rotary_limit_error"] = ang
    if name.startswith("chain_"):
        out["worst_pivot_gap"] = piv
    if name.startswith(STACKING_PREFIXES):
        starts = [vec(b.get("position"))[0] for b in desc["bodies"]]
        out["max_x_drift"] = max((abs(pose(body)[0][0] - x0) for body, x0, b
                                  in zip(bodies, starts, desc["bodies"]) if b["kind"] == "dynamic"),
                                 default=0.0)
    if left_out:
        out["left_out"] = ", ".join(f"{k} x{left_out.count(k)}" for k in sorted(set(left_out)))
    lib.b2DestroyWorld(world)
    return out


def run_ours(tamias, scene, steps, solver=None):
    """`tamias run SCENE --trusted --threads 1 [--solver KIND]`: its figures, by our key names."""
    cmd = [tamias, "run", scene, "--trusted", "--threads", "1", "--steps", str(steps)]
    if solver:
        cmd += ["--solver", solver]
    text = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    out = {}
    m = re.search(r"time per step: median ([0-9.]+) ms", text)
    if m:
        out["median_ms"] = float(m.group(1))
    for key in ("max penetration", "max joint error", "max limit overrun", "max x drift",
                "worst pivot gap"):
        m = re.search(rf"^{key}: ([-0-9.e]+)", text, re.M)
        if m:
            out[key.replace(" ", "_")] = float(m.group(1))
    return out


def lines(r):
    yield f"engine: {r['engine']}, {r['threads']} thread, {r['substeps']} sub-steps"
    yield f"scene {r['scene']}: {r['bodies']} bodies, {r['steps']} steps"
    yield f"time per step: median {r['median_ms']:.3f} ms, mean {r['mean_ms']:.3f} ms, total {r['total_s']:.2f} s"
    for key in ("max_penetration", "max_joint_error", "max_rotary_limit_error",
                "worst_pivot_gap", "max_x_drift", "sleeping_bodies", "left_out"):
        if key in r:
            val = r[key] if isinstance(r[key], (str, int)) else f"{r[key]:.6g}"
            yield f"{key.replace('_', ' ')}: {val}"


def cell(r, key, fmt):
    return fmt.format(r[key]) if key in r else "—"


def table(path):
    """The markdown table of the JSON lines in `path` (compare.sh)."""
    rows = [json.loads(line) for line in open(path) if line.strip()]
    print("| scene | Box2D ms/step | ours ms/step | ours ÷ Box2D | max penetration Box2D / ours "
          "| max joint error Box2D / ours | other (Box2D / ours) |")
    print("|---|---:|---:|---:|---:|---:|---|")
    for r in rows:
        o = r.get("ours", {})
        ratio = f"{o['median_ms'] / r['median_ms']:.2f}" if o.get("median_ms") and r["median_ms"] else "—"
        other = [f"{k.replace('_', ' ')} {cell(r, k, '{:.3g}')} / {cell(o, k, '{:.3g}')}"
                 for k in ("max_x_drift", "worst_pivot_gap") if k in r]
        if "max_rotary_limit_error" in r:
            other.append(f"rotary limit {r['max_rotary_limit_error']:.3g} rad / "
                         f"{cell(o, 'max_limit_overrun', '{:.3g}')}")
        if "left_out" in r:
            other.append(f"Box2D leaves out {r['left_out']}")
        print(f"| {r['scene']} | {r['median_ms']:.3f} | {cell(o, 'median_ms', '{:.3f}')} | {ratio} "
              f"| {cell(r, 'max_penetration', '{:.3g}')} / {cell(o, 'max_penetration', '{:.3g}')} "
              f"| {cell(r, 'max_joint_error', '{:.3g}')} / {cell(o, 'max_joint_error', '{:.3g}')} "
              f"| {'; '.join(other) or '—'} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene", nargs="?", help="scene JSON (tamias scene dump NAME -o FILE)")
    ap.add_argument("--steps", type=int, help="steps to run [default: the scene's]")
    ap.add_argument("--substeps", type=int, default=4, help="Box2D sub-steps [4, Box2D's default]")
    ap.add_argument("--threads", type=int, default=1, choices=[1], help="worker threads (only 1)")
    ap.add_argument("--no-sleep", action="store_true", help="turn Box2D's sleeping off")
    ap.add_argument("--every", type=int, default=1, help="measure quality every K steps [1]")
    ap.add_argument("--json", action="store_true", help="one JSON object instead of lines")
    ap.add_argument("--ours", metavar="TAMIAS", help="also run `TAMIAS run SCENE --threads 1`")
    ap.add_argument("--table", metavar="JSONL", help="print the markdown table of --json lines")
    ap.add_argument("--solver", choices=["sequential", "soft", "soft-narrow"],
                    help="our solver (`tamias run --solver`) [default: the scene's]")
    args = ap.parse_args()
    if args.table:
        return table(args.table)
    with open(args.scene) as f:
        desc = json.load(f)
    if args.no_sleep:  # ours too: an island never rests this long
        desc.setdefault("settings", {})["sleep_time_threshold"] = "1000000"
    steps = args.steps if args.steps is not None else desc["steps"]
    r = run(desc, steps, args.substeps, not args.no_sleep, max(1, args.every))
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
        print("\n".join(lines(r)))
        for k, v in r.get("ours", {}).items():
            print(f"ours {k.replace('_', ' ')}: {v}")


if __name__ == "__main__":
    sys.exit(main())
