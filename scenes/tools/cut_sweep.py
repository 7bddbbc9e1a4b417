#!/usr/bin/env python3
"""Sweep of `cuts` scenes on closed meshes: planes, wavy sheets and inner discs, end to end.

For each mesh (OBJ or OFF, closed) it draws seeded random cut surfaces, writes one scene per case
(`fracture.kind: "cuts"`), runs `fracref refine SCENE -o OUT` and `fracref check OUT`, and prints
a pass rate per mesh and per cut type. A case passes when both exit 0. A failure is put in the
stage it came from: `coarse` (the run also fails with --stop-after preprocess), `refine` (it
fails with --stop-after refine), `pieces` (it passes --stop-after refine: the pieces stage, or
animate when the scene had an animation, which these do not), `check` (the run passed,
`fracref check` did not), or `timeout`.

  python3 scenes/tools/cut_sweep.py --meshes .cache/meshes --out /tmp/sweep
  python3 scenes/tools/cut_sweep.py --planes 4 --wavy 0 --discs 0 --mesh bunny --cells 32

Cuts:
  plane  a flat square through a random point inside the object, random normal, 1.5 times the
         object's bounding-box diagonal across (so it reaches past B on every side);
  wavy   the same square displaced along its normal by a sine pattern (amplitude 3% of the
         diagonal);
  disc   a flat disc around a point at least 6% of the diagonal deep, its radius 60% of that
         depth (it never reaches B).
Python 3 standard library only; the same --seed gives the same cases.
"""
import argparse
import json
import math
import os
import random
import shutil
import subprocess
import sys
import time


def read_mesh(path):
    """Vertices and triangles of an OBJ or OFF file (polygons fanned)."""
    verts, tris = [], []
    with open(path) as f:
        text = f.read()
    if path.lower().endswith(".off"):
        tok = [t for line in text.splitlines() for t in line.split("#")[0].split()]
        assert tok[0].upper() == "OFF", path
        nv, nf = int(tok[1]), int(tok[2])
        k = 4
        for _ in range(nv):
            verts.append(tuple(float(x) for x in tok[k:k + 3]))
            k += 3
        for _ in range(nf):
            n = int(tok[k])
            idx = [int(x) for x in tok[k + 1:k + 1 + n]]
            k += 1 + n
            for i in range(1, n - 1):
                tris.append((idx[0], idx[i], idx[i + 1]))
        return verts, tris
    for line in text.splitlines():
        p = line.split()
        if not p:
            continue
        if p[0] == "v":
            verts.append((float(p[1]), float(p[2]), float(p[3])))
        elif p[0] == "f":
            idx = [int(x.split("/")[0]) for x in p[1:]]
            idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
            for i in range(1, len(idx) - 1):
                tris.append((idx[0], idx[i], idx[i + 1]))
    return verts, tris


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    n = math.sqrt(dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


class Solid:
    """Inside test (parity of a +z ray, triangles bucketed by their xy box) and depth bound."""

    def __init__(self, verts, tris, grid=64):
        self.v, self.t = verts, tris
        xs, ys, zs = zip(*verts)
        self.lo = (min(xs), min(ys), min(zs))
        self.hi = (max(xs), max(ys), max(zs))
        self.diag = math.dist(self.lo, self.hi)
        self.n = grid
        self.cells = {}
        for k, (a, b, c) in enumerate(tris):
            pa, pb, pc = verts[a], verts[b], verts[c]
            i0, j0 = self.cell(min(pa[0], pb[0], pc[0]), min(pa[1], pb[1], pc[1]))
            i1, j1 = self.cell(max(pa[0], pb[0], pc[0]), max(pa[1], pb[1], pc[1]))
            for i in range(i0, i1 + 1):
                for j in range(j0, j1 + 1):
                    self.cells.setdefault((i, j), []).append(k)
        self.boxes = [(tuple(min(verts[i][a] for i in t) for a in range(3)),
                       tuple(max(verts[i][a] for i in t) for a in range(3))) for t in tris]
        # Vertices bucketed in 3-D for the depth bound.
        self.h3 = self.diag / 32
        self.vcells = {}
        for k, p in enumerate(verts):
            self.vcells.setdefault(self.cell3(p), []).append(k)

    def cell(self, x, y):
        fx = (x - self.lo[0]) / max(self.hi[0] - self.lo[0], 1e-300)
        fy = (y - self.lo[1]) / max(self.hi[1] - self.lo[1], 1e-300)
        return (min(self.n - 1, max(0, int(fx * self.n))), min(self.n - 1, max(0, int(fy * self.n))))

    def cell3(self, p):
        return tuple(int(math.floor((p[a] - self.lo[a]) / self.h3)) for a in range(3))

    def inside(self, p):
        count = 0
        for k in self.cells.get(self.cell(p[0], p[1]), []):
            a, b, c = (self.v[i] for i in self.t[k])
            # Barycentric in xy, then the z of the hit.
            d = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1])
            if d == 0:
                continue
            l1 = ((b[1] - c[1]) * (p[0] - c[0]) + (c[0] - b[0]) * (p[1] - c[1])) / d
            l2 = ((c[1] - a[1]) * (p[0] - c[0]) + (a[0] - c[0]) * (p[1] - c[1])) / d
            l3 = 1 - l1 - l2
            if l1 < 0 or l2 < 0 or l3 < 0:
                continue
            if l1 * a[2] + l2 * b[2] + l3 * c[2] > p[2]:
                count += 1
        return count % 2 == 1

    def depth(self, p):
        """The distance from p to B: exact, over the triangles whose box is within reach of the
        nearest vertex (an upper bound) found in the 3-D buckets."""
        c = self.cell3(p)
        upper = math.inf
        r = 0
        while upper == math.inf or upper > r * self.h3:
            for i in range(c[0] - r, c[0] + r + 1):
                for j in range(c[1] - r, c[1] + r + 1):
                    for k in range(c[2] - r, c[2] + r + 1):
                        if max(abs(i - c[0]), abs(j - c[1]), abs(k - c[2])) != r:
                            continue
                        for v in self.vcells.get((i, j, k), []):
                            upper = min(upper, math.dist(p, self.v[v]))
            r += 1
            if r > 64:
                break
        best = upper
        for k, box in enumerate(self.boxes):
            if any(p[a] < box[0][a] - best or p[a] > box[1][a] + best for a in range(3)):
                continue
            best = min(best, point_triangle_distance(p, *(self.v[i] for i in self.t[k])))
        return best

    def random_inside(self, rng, min_depth=0.0):
        for _ in range(100000):
            p = tuple(rng.uniform(self.lo[a], self.hi[a]) for a in range(3))
            if self.inside(p) and (min_depth <= 0 or self.depth(p) >= min_depth):
                return p
        raise RuntimeError("no inside point found")


def point_triangle_distance(p, a, b, c):
    """Distance from p to the triangle abc (Ericson, Real-Time Collision Detection 5.1.5)."""
    ab, ac, ap = sub(b, a), sub(c, a), sub(p, a)
    d1, d2 = dot(ab, ap), dot(ac, ap)
    if d1 <= 0 and d2 <= 0:
        return math.dist(p, a)
    bp = sub(p, b)
    d3, d4 = dot(ab, bp), dot(ac, bp)
    if d3 >= 0 and d4 <= d3:
        return math.dist(p, b)
    vc = d1 * d4 - d3 * d2
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        v = d1 / (d1 - d3)
        return math.dist(p, tuple(a[i] + v * ab[i] for i in range(3)))
    cp = sub(p, c)
    d5, d6 = dot(ab, cp), dot(ac, cp)
    if d6 >= 0 and d5 <= d6:
        return math.dist(p, c)
    vb = d5 * d2 - d1 * d6
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        w = d2 / (d2 - d6)
        return math.dist(p, tuple(a[i] + w * ac[i] for i in range(3)))
    va = d3 * d6 - d5 * d4
    if va <= 0 and (d4 - d3) >= 0 and (d5 - d6) >= 0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return math.dist(p, tuple(b[i] + w * (c[i] - b[i]) for i in range(3)))
    denom = 1.0 / (va + vb + vc)
    v, w = vb * denom, vc * denom
    return math.dist(p, tuple(a[i] + ab[i] * v + ac[i] * w for i in range(3)))


def frame(n):
    u = norm(cross(n, (1.0, 0.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0, 0.0)))
    return u, cross(n, u)


def random_normal(rng):
    while True:
        v = (rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1))
        if dot(v, v) > 1e-6:
            return norm(v)


def sheet(center, n, half, k, bump=None):
    """A (k+1)^2 grid of the square of half-size `half` in the plane (center, n); bump(s, t) offsets along n."""
    u, v = frame(n)
    verts, tris = [], []
    for j in range(k + 1):
        for i in range(k + 1):
            s, t = -half + 2 * half * i / k, -half + 2 * half * j / k
            h = bump(s, t) if bump else 0.0
            verts.append(tuple(center[a] + s * u[a] + t * v[a] + h * n[a] for a in range(3)))
    for j in range(k):
        for i in range(k):
            a = j * (k + 1) + i
            tris += [(a, a + 1, a + k + 2), (a, a + k + 2, a + k + 1)]
    return verts, tris


def disc(center, n, radius, segments=32, rings=4):
    u, v = frame(n)
    verts, tris = [center], []
    for r in range(1, rings + 1):
        for s in range(segments):
            ang = 2 * math.pi * s / segments
            rr = radius * r / rings
            verts.append(tuple(center[a] + rr * (math.cos(ang) * u[a] + math.sin(ang) * v[a]) for a in range(3)))
    ring = lambda r, s: 1 + (r - 1) * segments + s % segments
    for s in range(segments):
        tris.append((0, ring(1, s), ring(1, s + 1)))
    for r in range(1, rings):
        for s in range(segments):
            a, b, c, d = ring(r, s), ring(r, s + 1), ring(r + 1, s), ring(r + 1, s + 1)
            tris += [(a, c, d), (a, d, b)]
    return verts, tris


def write_obj(path, verts, tris):
    with open(path, "w") as f:
        for p in verts:
            f.write("v %.9g %.9g %.9g\n" % p)
        for t in tris:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def make_cases(name, solid, args):
    rng = random.Random("%s:%d" % (name, args.seed))
    d = solid.diag
    cases = []
    for i in range(args.planes):
        c, n = solid.random_inside(rng), random_normal(rng)
        cases.append(("plane", i, sheet(c, n, 0.75 * d, 4)))
    for i in range(args.wavy):
        c, n = solid.random_inside(rng), random_normal(rng)
        f1, f2 = rng.uniform(1.5, 3.0), rng.uniform(1.5, 3.0)
        p1, p2 = rng.uniform(0, 2 * math.pi), rng.uniform(0, 2 * math.pi)
        amp = 0.03 * d
        bump = lambda s, t, f1=f1, f2=f2, p1=p1, p2=p2: amp * math.sin(2 * math.pi * f1 * s / d + p1) * math.cos(
            2 * math.pi * f2 * t / d + p2)
        cases.append(("wavy", i, sheet(c, n, 0.75 * d, 40, bump)))
    for i in range(args.discs):
        c = solid.random_inside(rng, 0.06 * d)
        cases.append(("disc", i, disc(c, random_normal(rng), 0.6 * solid.depth(c))))
    return cases


def last_line(text):
    """The error: fracref's first 'fracref:' line, with the line after it when there is one."""
    lines = [l.strip() for l in text.strip().splitlines() if l.strip()]
    for k, l in enumerate(lines):
        if l.startswith("fracref:"):
            return " / ".join(lines[k:k + 2])
    return lines[-1] if lines else ""


def run_case(args, mesh_path, kind, index, geometry, case_dir):
    os.makedirs(case_dir, exist_ok=True)
    write_obj(os.path.join(case_dir, "cut.obj"), *geometry)
    fracture = {"kind": "cuts", "mesh": "cut.obj"}
    if args.cells:
        fracture["cells_per_diagonal"] = args.cells
    scene = {"exterior": os.path.abspath(mesh_path), "fracture": fracture,
             "field": {"type": "marble", "resolution": [args.field] * 3},
             "refine": {"max_iterations": args.iterations}}
    with open(os.path.join(case_dir, "scene.json"), "w") as f:
        json.dump(scene, f, indent=1)
    out = os.path.join(case_dir, "out")
    base = [args.fracref, "refine", os.path.join(case_dir, "scene.json"), "-o", out, "-q", "--backend", "cpu",
            "--threads", str(args.threads)]
    for s in args.set:
        base += ["--set", s]
    t0 = time.time()
    try:
        r = subprocess.run(base, capture_output=True, text=True, timeout=args.timeout)
    except subprocess.TimeoutExpired:
        return "timeout", "more than %d s" % args.timeout, time.time() - t0
    seconds = time.time() - t0
    if r.returncode != 0:
        msg = "exit %d: %s" % (r.returncode, last_line(r.stderr))
        for stage in ("preprocess", "refine"):
            try:
                pre = subprocess.run(base[:4] + [out + "_pre"] + base[5:] + ["--stop-after", stage],
                                     capture_output=True, text=True, timeout=args.timeout)
                failed = pre.returncode != 0
            except subprocess.TimeoutExpired:
                failed = True
            shutil.rmtree(out + "_pre", ignore_errors=True)
            if failed:
                return ("coarse" if stage == "preprocess" else "refine"), msg, seconds
        return "pieces", msg, seconds
    try:
        with open(os.path.join(out, "report.json")) as f:
            pieces = json.load(f).get("pieces")
    except (OSError, ValueError):
        pieces = None
    c = subprocess.run([args.fracref, "check", out], capture_output=True, text=True, timeout=args.timeout)
    if not args.keep:
        shutil.rmtree(out, ignore_errors=True)
    if c.returncode != 0:
        return "check", "check exit %d: %s" % (c.returncode, last_line(c.stdout + c.stderr)), seconds
    return "pass", "%s pieces" % pieces, seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fracref", default="build/fracref")
    ap.add_argument("--meshes", default=".cache/meshes", help="folder of closed OBJ/OFF meshes")
    ap.add_argument("--mesh", action="append", default=[], help="only meshes whose name contains this (repeatable)")
    ap.add_argument("--out", default="/tmp/cut_sweep")
    ap.add_argument("--planes", type=int, default=12)
    ap.add_argument("--wavy", type=int, default=4)
    ap.add_argument("--discs", type=int, default=4)
    ap.add_argument("--only", default="", help="comma-separated case names to run, e.g. bunny/plane03")
    ap.add_argument("--cells", type=float, default=0, help="fracture.cells_per_diagonal (0: the scene default)")
    ap.add_argument("--field", type=int, default=32, help="field.resolution per axis")
    ap.add_argument("--iterations", type=int, default=40, help="refine.max_iterations")
    ap.add_argument("--set", action="append", default=[], help="passed to fracref refine --set (repeatable)")
    ap.add_argument("--timeout", type=int, default=300, help="seconds per fracref run")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--keep", action="store_true", help="keep each passing case's output folder")
    ap.add_argument("--json", default="", help="write every case's result to this file")
    ap.add_argument("--summarize", nargs="+", default=[], help="only print the table of these --json files")
    args = ap.parse_args()
    if args.summarize:
        summarize([r for f in args.summarize for r in json.load(open(f))])
        return 0

    names = sorted(f for f in os.listdir(args.meshes) if f.lower().endswith((".obj", ".off")))
    if args.mesh:
        names = [n for n in names if any(m in n for m in args.mesh)]
    only = set(x for x in args.only.split(",") if x)
    results = []
    for name in names:
        stem = os.path.splitext(name)[0]
        path = os.path.join(args.meshes, name)
        solid = Solid(*read_mesh(path))
        for kind, index, geometry in make_cases(stem, solid, args):
            case = "%s/%s%02d" % (stem, kind, index)
            if only and case not in only:
                continue
            status, msg, seconds = run_case(args, path, kind, index, geometry, os.path.join(args.out, case))
            results.append({"case": case, "mesh": stem, "kind": kind, "status": status, "message": msg,
                            "seconds": round(seconds, 1)})
            print("%-28s %-8s %6.1fs %s" % (case, status, seconds, msg[:160]), flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    summarize(results)
    return 0


def summarize(results):
    stages = ["coarse", "refine", "pieces", "check", "timeout"]
    def row(label, rs):
        ok = sum(r["status"] == "pass" for r in rs)
        cells = ["%d" % sum(r["status"] == s for r in rs) for s in stages]
        return "| %s | %d/%d | %.0f%% | %s |" % (label, ok, len(rs), 100.0 * ok / max(1, len(rs)), " | ".join(cells))
    print("\n| cases | pass | rate | " + " | ".join(stages) + " |")
    print("|---|---:|---:|" + "---:|" * len(stages))
    for mesh in sorted(set(r["mesh"] for r in results)):
        print(row(mesh, [r for r in results if r["mesh"] == mesh]))
    for kind in ["plane", "wavy", "disc"]:
        rs = [r for r in results if r["kind"] == kind]
        if rs:
            print(row("all " + kind + "s", rs))
    print(row("all", results))


if __name__ == "__main__":
    sys.exit(main())
