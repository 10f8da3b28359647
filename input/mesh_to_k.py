#!/usr/bin/python3
"""Convert a mesh from another pre-processor into a mefem (LS-DYNA) keyword include file.

    /usr/bin/python3 input/mesh_to_k.py MESH [-o MESH.k] [--scale S] [--shells TAG ...]

MESH is any format Debian's python3-meshio reads (by its extension): Gmsh .msh (2.2 and 4.1),
Abaqus .inp, Nastran bulk data (.bdf, .nas, .fem), VTK .vtu/.vtk, MED, ... The output holds
*NODE, *ELEMENT_SOLID (tetrahedra, hexahedra, pentahedra as LS-DYNA's degenerate hexahedra),
*ELEMENT_SHELL (for 2D meshes, and for the groups named with --shells: rigid tool sheets),
and sets; include it from a deck that adds the *PART, *SECTION, *MAT, loads and controls
(doc/first_model.md).

Parts: the cells' groups become parts, numbered by the group's tag (Gmsh physical groups:
their tag; Abaqus ELSETs and other named cell sets: 1, 2, ... in the order read); cells in no
group go to part 1 (or to the next free number when groups exist). The cells of the mesh's
highest dimension are the elements; lower-dimensional cells in a group (Gmsh physical
surfaces of a 3D mesh, physical curves of a 2D one) become *SET_SEGMENT_TITLE (their faces or
edges, oriented outward from the element they bound) and *SET_NODE_LIST_TITLE (their nodes),
numbered by their tag; named point sets (Abaqus NSET) become *SET_NODE_LIST_TITLE. Node and
element ids are 1, 2, ... in the mesh's order.

Orientation: every element is checked and turned where its volume (2D: area) is negative
(tetrahedra N2 and N3 swapped, hexahedra and pentahedra top and bottom swapped, triangles and
quadrilaterals reversed); the count is printed. A degenerate element (zero volume) is an
error. --scale multiplies the coordinates (e.g. 1000 from metres to millimetres: the deck's
units must agree with its material data).
"""
import argparse
import os
import sys

import numpy as np

SOLID_TYPES = ('tetra', 'hexahedron', 'wedge')
SHELL_TYPES = ('triangle', 'quad')
LINE_TYPES = ('line',)
DIMENSION = {'tetra': 3, 'hexahedron': 3, 'wedge': 3, 'triangle': 2, 'quad': 2, 'line': 1,
             'vertex': 0}
# faces (3D) and edges (2D) of each element type, in the mesh's (VTK) node order, each a cycle
FACES = {
    'tetra': [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)],
    'hexahedron': [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6),
                   (3, 0, 4, 7)],
    'wedge': [(0, 2, 1), (3, 4, 5), (0, 1, 4, 3), (1, 2, 5, 4), (2, 0, 3, 5)],
    'triangle': [(0, 1), (1, 2), (2, 0)],
    'quad': [(0, 1), (1, 2), (2, 3), (3, 0)],
}


def tet_volume(x, t):
    return np.einsum('ij,ij->i', np.cross(x[t[:, 1]] - x[t[:, 0]], x[t[:, 2]] - x[t[:, 0]]),
                     x[t[:, 3]] - x[t[:, 0]]) / 6.0


def volumes(kind, x, conn):
    """Signed volume (area in 2D) of every cell of one type."""
    if kind == 'tetra':
        return tet_volume(x, conn)
    if kind == 'hexahedron':
        split = [(0, 1, 2, 6), (0, 2, 3, 6), (0, 3, 7, 6), (0, 7, 4, 6), (0, 4, 5, 6),
                 (0, 5, 1, 6)]
        return sum(tet_volume(x, conn[:, list(s)]) for s in split)
    if kind == 'wedge':
        split = [(0, 1, 2, 3), (1, 2, 3, 4), (2, 3, 4, 5)]
        return sum(tet_volume(x, conn[:, list(s)]) for s in split)
    if kind in SHELL_TYPES:
        area = 0.0
        for k in range(1, conn.shape[1] - 1):
            a, b = x[conn[:, k]] - x[conn[:, 0]], x[conn[:, k + 1]] - x[conn[:, 0]]
            area = area + 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
        return area
    raise ValueError(kind)


def turned(kind, conn):
    """The cells with the opposite orientation."""
    c = conn.copy()
    if kind == 'tetra':
        c[:, [1, 2]] = c[:, [2, 1]]
    elif kind == 'hexahedron':
        c = c[:, [4, 5, 6, 7, 0, 1, 2, 3]]
    elif kind == 'wedge':
        c = c[:, [3, 4, 5, 0, 1, 2]]
    else:
        c = c[:, ::-1]
    return c


def lsdyna_solid(kind, cell):
    """The 8 node numbers of an *ELEMENT_SOLID card (1-based)."""
    n = [int(v) + 1 for v in cell]
    if kind == 'tetra':
        return n + [n[3]] * 4
    if kind == 'wedge':
        # LS-DYNA's pentahedron is a hexahedron with N5 = N6 and N7 = N8: its triangles are
        # (N1, N2, N5) and (N4, N3, N6), and the quadrilateral N1-N2-N3-N4 turns (right hand)
        # towards the edge N5-N6, as a positive hexahedron's bottom turns towards its top.
        # The wedge (a, b, c) below (d, e, f), a-b-c counter-clockwise seen from above: the
        # quadrilateral below the edge c-f is b-a-d-e.
        a, b, c, d, e, f = n
        return [b, a, d, e, c, c, f, f]
    return n


def cell_groups(mesh):
    """Per cell block, the group tag of each cell (0: none), and the names of the groups."""
    tags = [np.zeros(len(block.data), dtype=int) for block in mesh.cells]
    names = {}
    if 'gmsh:physical' in mesh.cell_data:
        for k, data in enumerate(mesh.cell_data['gmsh:physical']):
            tags[k] = np.asarray(data, dtype=int)
        for name, (tag, dim) in getattr(mesh, 'field_data', {}).items():
            names[int(tag)] = name
        return tags, names
    next_tag = 1
    for name, per_block in mesh.cell_sets.items():
        if name.startswith('gmsh:'):
            continue
        for k, members in enumerate(per_block):
            if members is None or len(members) == 0:
                continue
            tags[k][np.asarray(members, dtype=int)] = next_tag
        names[next_tag] = name
        next_tag += 1
    return tags, names


def oriented_faces(kind, conn, x, faces_wanted):
    """For lower-dimensional cells (faces_wanted: tuples of node numbers), the same faces as
    cycles that turn outward from the element of `conn` they bound (None when none does)."""
    index = {}
    for e, cell in enumerate(conn):
        for face in FACES[kind]:
            nodes = tuple(int(cell[i]) for i in face)
            index[tuple(sorted(nodes))] = nodes
    return [index.get(tuple(sorted(int(v) for v in f))) for f in faces_wanted]


def convert(path, output, scale=1.0, shell_tags=()):
    import meshio
    mesh = meshio.read(path)
    x = np.asarray(mesh.points, dtype=float) * scale
    if x.shape[1] == 2:
        x = np.hstack([x, np.zeros((len(x), 1))])
    tags, names = cell_groups(mesh)
    kinds = [block.type for block in mesh.cells]
    top = max(DIMENSION.get(k, -1) for k in kinds)
    if top < 2:
        raise SystemExit('%s: no surface or volume cells (types %s)' % (path, sorted(set(kinds))))
    if top == 2 and np.any(abs(x[:, 2]) > 1e-12 * max(1.0, np.abs(x).max())):
        raise SystemExit('%s: a 2D mesh must lie in the plane z = 0 (plane strain, x-y)' % path)
    used_tags = sorted({int(t) for k, t_block in enumerate(tags) if DIMENSION.get(kinds[k]) == top
                        for t in t_block if t > 0})
    free_part = 1 if not used_tags else max(used_tags) + 1
    solids, shells, turned_count = [], [], 0
    element_blocks = []
    for k, block in enumerate(mesh.cells):
        kind = block.type
        conn = np.asarray(block.data, dtype=int)
        as_shell = kind in SHELL_TYPES and (top == 2 or any(t in shell_tags for t in tags[k]))
        if DIMENSION.get(kind) != top and not as_shell:
            continue
        if kind not in SOLID_TYPES + SHELL_TYPES:
            raise SystemExit('%s: cells of type %s are not supported (tetra, hexahedron, wedge, '
                             'triangle, quad)' % (path, kind))
        if DIMENSION[kind] == top:
            v = volumes(kind, x, conn)
            bad = v < 0
            if np.any(v == 0):
                raise SystemExit('%s: %d %s cells have zero volume' % (path, int(np.sum(v == 0)),
                                                                         kind))
            conn[bad] = turned(kind, conn[bad])
            turned_count += int(bad.sum())
            element_blocks.append((kind, conn))
        parts = np.where(tags[k] > 0, tags[k], free_part)
        for cell, part in zip(conn, parts):
            if kind in SOLID_TYPES:
                solids.append((int(part), lsdyna_solid(kind, cell)))
            else:
                n = [int(v) + 1 for v in cell]
                shells.append((int(part), n + [n[-1]] * (4 - len(n))))
    # sets from the lower-dimensional cells in groups, and from named point sets
    segment_sets, node_sets = {}, {}
    for k, block in enumerate(mesh.cells):
        kind = block.type
        if DIMENSION.get(kind) != top - 1 or kind in SHELL_TYPES and any(
                t in shell_tags for t in tags[k]):
            continue
        conn = np.asarray(block.data, dtype=int)
        for tag in sorted({int(t) for t in tags[k] if t > 0}):
            members = conn[tags[k] == tag]
            faces = [None] * len(members)
            for ekind, econn in element_blocks:
                found = oriented_faces(ekind, econn, x, members)
                faces = [f if f is not None else g for f, g in zip(faces, found)]
            segment_sets.setdefault(tag, []).extend(
                f if f is not None else tuple(int(v) for v in m) for f, m in zip(faces, members))
            node_sets.setdefault(tag, set()).update(int(v) for v in members.ravel())
    next_set = max([0] + list(segment_sets)) + 1
    for name, members in mesh.point_sets.items():
        if name.startswith('gmsh:'):
            continue
        node_sets[next_set] = set(int(v) for v in np.asarray(members).ravel())
        names[next_set] = name
        next_set += 1
    write(output, path, x, solids, shells, segment_sets, node_sets, names, turned_count)
    print('%s: %d nodes, %d solids, %d shells, parts %s, %d segment sets, %d node sets; %d '
          'elements turned to a positive volume' % (output, len(x), len(solids), len(shells),
                                                    sorted({p for p, _ in solids + shells}),
                                                    len(segment_sets), len(node_sets),
                                                    turned_count))


def write(output, source, x, solids, shells, segment_sets, node_sets, names, turned_count):
    lines = ['$ mefem include written by input/mesh_to_k.py from %s' % os.path.basename(source),
             '$ %d nodes, %d solid and %d shell elements; %d turned to a positive volume'
             % (len(x), len(solids), len(shells), turned_count),
             '*NODE', '$#   nid               x               y               z']
    lines += ['%8d%16.9e%16.9e%16.9e' % (k + 1, p[0], p[1], p[2]) for k, p in enumerate(x)]
    if solids:
        lines += ['*ELEMENT_SOLID', '$#   eid     pid      n1      n2      n3      n4      n5'
                  '      n6      n7      n8']
        lines += ['%8d%8d' % (e + 1, part) + ''.join('%8d' % v for v in n)
                  for e, (part, n) in enumerate(solids)]
    if shells:
        lines += ['*ELEMENT_SHELL', '$#   eid     pid      n1      n2      n3      n4']
        first = len(solids) + 1
        lines += ['%8d%8d' % (first + e, part) + ''.join('%8d' % v for v in n)
                  for e, (part, n) in enumerate(shells)]
    for sid in sorted(segment_sets):
        lines += ['*SET_SEGMENT_TITLE', names.get(sid, 'group %d' % sid)[:80], '%10d' % sid]
        for f in segment_sets[sid]:
            n = [v + 1 for v in f]
            n = n + [n[-1]] * (4 - len(n))
            lines.append(''.join('%10d' % v for v in n))
    for sid in sorted(node_sets):
        members = sorted(node_sets[sid])
        lines += ['*SET_NODE_LIST_TITLE', names.get(sid, 'group %d' % sid)[:80], '%10d' % sid]
        for k in range(0, len(members), 8):
            lines.append(''.join('%10d' % (v + 1) for v in members[k:k + 8]))
    with open(output, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('mesh')
    ap.add_argument('-o', '--output', help='the include file (default: MESH with .k)')
    ap.add_argument('--scale', type=float, default=1.0, help='factor on the coordinates')
    ap.add_argument('--shells', type=int, nargs='*', default=[],
                    help='group tags whose triangles/quadrilaterals become shell elements '
                         '(rigid tool sheets) in a 3D mesh')
    a = ap.parse_args(argv)
    output = a.output or os.path.splitext(a.mesh)[0] + '.k'
    convert(a.mesh, output, a.scale, tuple(a.shells))


if __name__ == '__main__':
    main(sys.argv[1:])
