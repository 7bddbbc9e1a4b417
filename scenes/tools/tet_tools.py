#!/usr/bin/env python3
"""What a scene needs around a labelled tet mesh from gmsh (MEDIT .mesh) or TetGen (.node/.ele).

  tet_tools.py boundary MESH OUT.obj          the exterior: the faces of one tet, wound outward
  tet_tools.py rigid MESH OUT.txt --frames N  per-label rigid transforms: each label drifts away
                                              from the centre and turns about z (INPUTS.md, Rigid);
                                              MESH may also be a pieces OBJ (one o/g group a piece)
  tet_tools.py frames MESH OUT_DIR --frames N per-frame positions of every vertex (a twist about
                                              z growing with height): OUT_DIR/frame_0000.txt ...

MESH is a .mesh, or a TetGen .ele / .node (its partner beside it). Labels are numbered as
fracref numbers pieces: in ascending order. Plain Python 3, no dependencies; the output depends
only on the input.
"""
import argparse
import math
import os
import sys


def read_medit(path):
    tokens = []
    with open(path) as f:
        for line in f:
            line = line.split("#")[0].strip()
            if line:
                tokens.append(line.split())
    verts, tets, i = [], [], 0
    while i < len(tokens):
        key = tokens[i][0]
        if key in ("Vertices", "Tetrahedra"):
            count = int(tokens[i][1]) if len(tokens[i]) > 1 else int(tokens[i + 1][0])
            start = i + 1 if len(tokens[i]) > 1 else i + 2
            rows = tokens[start:start + count]
            if key == "Vertices":
                verts = [tuple(float(x) for x in r[:3]) for r in rows]
            else:
                tets = [(tuple(int(x) - 1 for x in r[:4]), int(r[4])) for r in rows]
            i = start + count
        else:
            i += 1
    return verts, tets


def read_tetgen(path):
    stem = os.path.splitext(path)[0]
    def rows(p):
        with open(p) as f:
            return [l.split("#")[0].split() for l in f if l.split("#")[0].strip()]
    node, ele = rows(stem + ".node"), rows(stem + ".ele")
    base = int(node[1][0])
    verts = [tuple(float(x) for x in r[1:4]) for r in node[1:]]
    has_attr = int(ele[0][2]) > 0
    tets = [(tuple(int(x) - base for x in r[1:5]), int(float(r[5])) if has_attr else 0) for r in ele[1:]]
    return verts, tets


def read_obj_pieces(path):
    """An OBJ with one `o`/`g` group per piece, as 'tets' labelled by group (for rigid only)."""
    verts, groups = [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                verts.append(tuple(float(x) for x in t[1:4]))
            elif t[0] in ("o", "g"):
                groups.append(set())
            elif t[0] == "f" and groups:
                groups[-1].update(int(x.split("/")[0]) - 1 for x in t[1:])
    return verts, [((v, v, v, v), g) for g, used in enumerate(groups) for v in sorted(used)]


def read(path):
    if path.endswith(".obj"):
        return read_obj_pieces(path)
    return read_medit(path) if path.endswith(".mesh") else read_tetgen(path)


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def det(a, b, c):
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])


def boundary(verts, tets):
    """Faces of one tet, wound outward (the tet's fourth corner behind them)."""
    count, face_of = {}, {}
    for (a, b, c, d), _ in tets:
        if det(sub(verts[b], verts[a]), sub(verts[c], verts[a]), sub(verts[d], verts[a])) < 0:
            b, c = c, b
        for f in ((a, c, b), (a, b, d), (a, d, c), (b, c, d)):
            k = tuple(sorted(f))
            count[k] = count.get(k, 0) + 1
            face_of[k] = f
    return [face_of[k] for k in sorted(count) if count[k] == 1]


def write_boundary(verts, tets, out):
    faces = boundary(verts, tets)
    used = sorted({v for f in faces for v in f})
    index = {v: i + 1 for i, v in enumerate(used)}
    with open(out, "w") as f:
        f.write("# exterior: the boundary faces of the tet mesh\n")
        for v in used:
            f.write("v %.17g %.17g %.17g\n" % verts[v])
        for a, b, c in faces:
            f.write("f %d %d %d\n" % (index[a], index[b], index[c]))


def centre(points):
    n = float(len(points))
    return tuple(sum(p[k] for p in points) / n for k in range(3))


def write_rigid(verts, tets, out, frames):
    labels = sorted({l for _, l in tets})
    whole = centre(verts)
    with open(out, "w") as f:
        f.write("# frame piece  r00 r01 r02 t0  r10 r11 r12 t1  r20 r21 r22 t2\n")
        for frame in range(frames):
            s = frame / max(frames - 1, 1)
            for piece, label in enumerate(labels):
                c = centre([verts[v] for t, l in tets if l == label for v in t])
                d = sub(c, whole)
                angle = 0.3 * s * (1 if piece % 2 == 0 else -1)
                co, si = math.cos(angle), math.sin(angle)
                # turn about the piece's centre c, then move it away from the middle by 0.5 d
                t = (c[0] - (co * c[0] - si * c[1]) + 0.5 * s * d[0], c[1] - (si * c[0] + co * c[1]) + 0.5 * s * d[1],
                     0.5 * s * d[2])
                f.write("%d %d  %.17g %.17g 0 %.17g  %.17g %.17g 0 %.17g  0 0 1 %.17g\n" %
                        (frame, piece, co, -si, t[0], si, co, t[1], t[2]))


def write_frames(verts, out_dir, frames):
    os.makedirs(out_dir, exist_ok=True)
    lo = min(v[2] for v in verts)
    hi = max(v[2] for v in verts)
    for frame in range(frames):
        s = frame / max(frames - 1, 1)
        with open(os.path.join(out_dir, "frame_%04d.txt" % frame), "w") as f:
            for x, y, z in verts:
                a = 0.6 * s * (z - lo) / max(hi - lo, 1e-30)
                f.write("%.9g %.9g %.9g\n" % (math.cos(a) * x - math.sin(a) * y, math.sin(a) * x + math.cos(a) * y, z))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("what", choices=["boundary", "rigid", "frames"])
    p.add_argument("mesh")
    p.add_argument("out")
    p.add_argument("--frames", type=int, default=8)
    a = p.parse_args()
    verts, tets = read(a.mesh)
    if a.what == "boundary":
        write_boundary(verts, tets, a.out)
    elif a.what == "rigid":
        write_rigid(verts, tets, a.out, a.frames)
    else:
        write_frames(verts, a.out, a.frames)


if __name__ == "__main__":
    sys.exit(main())
