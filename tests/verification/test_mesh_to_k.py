"""input/mesh_to_k.py (issue 25): meshes of other pre-processors into keyword include files.
Meshes written through Debian's python3-meshio (the formats users bring) and by hand:
1. Gmsh 4.1 and 2.2: a block of 6 x 2 x 2 cubes of 6 tetrahedra, half of them with their
   node order turned (negative volume), physical volume 5 and physical surface 7 (the top's
   triangles): every element positive, part 5, segment set 7 of the top faces oriented
   outward (+z) and its node set;
2. Abaqus .inp by hand: two C3D8 hexahedra in two ELSETs (one given upside down) and an NSET;
3. Nastran bulk data: wedges (CPENTA) from a block of prisms, half of them upside down: all
   positive as LS-DYNA pentahedra (mefem --check rejects a negative volume);
4. Gmsh 2.2 meshes of the kinds Gmsh makes: a cylinder of tetrahedra and a mixed mesh of
   hexahedra beside tetrahedra (two physical volumes, two parts of two element kinds);
5. a 2D Gmsh mesh of triangles and quadrilaterals (a rigid part: plane strain takes
   quadrilaterals as rigid tools only) with a physical curve: *ELEMENT_SHELL and a segment set
   of edges.
Each include, wrapped in a deck (part, section, material, termination), passes `mefem --check`
with the right counts and each part's mass (density x volume, from the run log's summary);
the 3D Gmsh block also runs a few explicit cycles.
"""
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks, ROOT, run
from explicit_cases import box_tets, box_hexes

checks = Checks('mesh_to_k')
OUT = os.path.join(ROOT, 'tests', 'out', 'mesh_to_k')
os.makedirs(OUT, exist_ok=True)
CONVERTER = os.path.join(ROOT, 'input', 'mesh_to_k.py')
RHO = 7.85e-9                      # steel, t/mm^3
try:
    import meshio
except ImportError:
    meshio = None


def convert(mesh_path, extra=()):
    out = os.path.splitext(mesh_path)[0] + '.k'
    p = subprocess.run([sys.executable, CONVERTER, mesh_path, '-o', out] + list(extra),
                       capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr, out


def deck_around(include, parts, shells=False, end_time=0.0, elform=10, rigid=(), sheets={},
                elforms={}):
    """A deck that includes the mesh and gives each part a section (solids: ELFORM `elform`,
    or elforms[part]) and a material (the parts in `rigid`: *MAT_RIGID of the same density);
    `sheets` {part: thickness}: rigid shell parts of a 3D mesh."""
    name = os.path.splitext(include)[0] + '_deck.k'
    lines = ['*KEYWORD', '*INCLUDE', os.path.basename(include)]
    for p in parts:
        lines += ['*PART', 'part %d' % p, '%10d%10d%10d' % (p, 10 + p if p in elforms else 1,
                                                          2 if p in rigid else 1)]
        if p in elforms:
            lines += ['*SECTION_SOLID', '%10d%10d' % (10 + p, elforms[p])]
    for p, t in sheets.items():
        lines += ['*PART', 'sheet %d' % p, '%10d%10d%10d' % (p, 100 + p, 2),
                  '*SECTION_SHELL', '%10d%10d' % (100 + p, 2), '%10.3f' % t]
    if shells:
        lines += ['*SECTION_SHELL', '%10d%10d' % (1, 43), '%10.1f' % 1.0]
    else:
        lines += ['*SECTION_SOLID', '%10d%10d' % (1, elform)]
    lines += ['*MAT_ELASTIC', '%10d%10.3e%10.1f%10.2f' % (1, RHO, 210000.0, 0.3)]
    if rigid or sheets:
        lines += ['*MAT_RIGID', '%10d%10.3e%10.1f%10.2f' % (2, RHO, 210000.0, 0.3),
                  '%10.1f' % 0.0, '']
    if end_time > 0:
        lines += ['*INITIAL_VELOCITY', '%10d' % 0, '%10.1f%10.1f%10.1f' % (0.0, 0.0, 100.0),
                  '*CONTROL_TERMINATION', '%10.3e' % end_time]
    lines += ['*END']
    with open(name, 'w') as f:
        f.write('\n'.join(lines) + '\n')
    return name


def check_deck(deck, what, nodes, elements, masses):
    """--check accepts the deck, counts the nodes and elements, and its summary gives each
    part the mass density x volume of the meshed region (masses: {part: mass})."""
    p = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), '--check', deck],
                       capture_output=True, text=True)
    text = p.stdout + p.stderr
    want = 'model: %d nodes, %d elements' % (nodes, elements)
    checks.check(p.returncode == 0 and want in text, '%s: the deck around the include passes '
                 '--check (%s)' % (what, want), text[-600:])
    got = {int(m.group(1)): float(m.group(2))
           for m in re.finditer(r'part (\d+): .*, mass (\S+)', text)}
    total = re.search(r'total mass (\S+)', text)
    ok = set(got) == set(masses) and all(abs(got[k] - masses[k]) <= 1e-5 * masses[k]
                                         for k in masses) and total is not None and \
        abs(float(total.group(1)) - sum(masses.values())) <= 1e-5 * sum(masses.values())
    checks.check(ok, '%s: the summary\'s part masses are density x volume %s' % (what, masses),
                 'got %s, %s' % (got, total.group(0) if total else 'no total'))


def include_sets(path):
    """{(kind, id): card lines} of the *SET_ keywords of an include."""
    sets, current = {}, None
    lines = open(path).read().splitlines()
    k = 0
    while k < len(lines):
        line = lines[k]
        if line.startswith('*SET_'):
            kind = line.split('_')[1]
            sid = int(lines[k + 2])
            current = sets.setdefault((kind, sid), [])
            k += 3
            continue
        if line.startswith('*'):
            current = None
        elif current is not None and not line.startswith('$'):
            current.append([int(v) for v in line.split()])
        k += 1
    return sets


def write_gmsh41(path, x, tets, volume, surfaces):
    """An ASCII Gmsh 4.1 file as Gmsh writes it: physical names, entities (volume 1 in the
    physical group `volume` = (tag, name), surface k + 2 in the k-th of `surfaces` = [(tag,
    name, triangles)]), nodes in one entity block, tetrahedra (type 4) and triangles (type 2)."""
    lo, hi = x.min(axis=0), x.max(axis=0)
    box = ' '.join('%g' % v for v in list(lo) + list(hi))
    groups = [(2, t, n) for t, n, _ in surfaces] + [(3, volume[0], volume[1])]
    lines = ['$MeshFormat', '4.1 0 8', '$EndMeshFormat', '$PhysicalNames', str(len(groups))]
    lines += ['%d %d "%s"' % g for g in groups]
    lines += ['$EndPhysicalNames', '$Entities', '0 0 %d 1' % len(surfaces)]
    lines += ['%d %s 1 %d 0' % (k + 2, box, t) for k, (t, _, _) in enumerate(surfaces)]
    lines += ['1 %s 1 %d %d %s' % (box, volume[0], len(surfaces),
                                   ' '.join(str(k + 2) for k in range(len(surfaces)))),
              '$EndEntities', '$Nodes', '1 %d 1 %d' % (len(x), len(x)), '3 1 0 %d' % len(x)]
    lines += ['%d' % (k + 1) for k in range(len(x))]
    lines += ['%.17g %.17g %.17g' % tuple(p) for p in x]
    n = len(tets) + sum(len(f) for _, _, f in surfaces)
    lines += ['$EndNodes', '$Elements', '%d %d 1 %d' % (1 + len(surfaces), n, n),
              '3 1 4 %d' % len(tets)]
    lines += ['%d %s' % (e + 1, ' '.join(str(v + 1) for v in t)) for e, t in enumerate(tets)]
    first = len(tets) + 1
    for k, (_, _, faces) in enumerate(surfaces):
        lines += ['2 %d 2 %d' % (k + 2, len(faces))]
        lines += ['%d %s' % (first + e, ' '.join(str(v + 1) for v in f))
                  for e, f in enumerate(faces)]
        first += len(faces)
    lines += ['$EndElements']
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def plane_faces(x, tets, axis, value, outward):
    """The triangles of the tets' faces on the plane x[axis] = value, each turned against the
    outward normal (sign `outward`) on purpose: the converter orients them."""
    faces = []
    for t in tets:
        for face in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)):
            f = t[list(face)]
            if np.all(abs(x[f, axis] - value) < 1e-9):
                n = np.cross(x[f[1]] - x[f[0]], x[f[2]] - x[f[0]])[axis]
                faces.append(f[::-1] if n * outward > 0 else f)
    return np.array(faces)


def gmsh_block():
    x, tets = box_tets(6.0, 2.0, 2.0, 6, 2, 2)
    tets = np.array(tets)
    tets[::2] = tets[::2][:, [0, 2, 1, 3]]              # half of them turned inside out
    top = plane_faces(x, np.array(box_tets(6.0, 2.0, 2.0, 6, 2, 2)[1]), 2, 2.0, +1)
    for version in ('4.1', '2.2'):
        path = os.path.join(OUT, 'block_gmsh%s.msh' % version.replace('.', ''))
        if version == '4.1':
            write_gmsh41(path, x, tets, (5, 'billet'), [(7, 'top', top)])
        else:
            mesh = meshio.Mesh(x, [('tetra', tets), ('triangle', top)],
                               cell_data={'gmsh:physical': [np.full(len(tets), 5),
                                                            np.full(len(top), 7)],
                                          'gmsh:geometrical': [np.full(len(tets), 1),
                                                               np.full(len(top), 2)]},
                               field_data={'billet': np.array([5, 3]),
                                           'top': np.array([7, 2])})
            meshio.write(path, mesh, file_format='gmsh22', binary=False)
        rc, text, include = convert(path)
        print('    %s' % text.strip())
        checks.check(rc == 0 and ('%d elements turned' % (len(tets) // 2)) in text,
                     'Gmsh %s: converted, the turned tets counted' % version, text[-400:])
        if rc != 0:
            continue
        sets = include_sets(include)
        segments = sets.get(('SEGMENT', 7), [])
        xs = np.array([[x[v - 1] for v in s[:3]] for s in segments])
        normals = np.cross(xs[:, 1] - xs[:, 0], xs[:, 2] - xs[:, 0]) if len(xs) else np.zeros(
            (0, 3))
        checks.check(len(segments) == len(top) and np.all(normals[:, 2] > 0) and
                     ('NODE', 7) in sets, 'Gmsh %s: the physical surface as a segment set '
                     'oriented outward (+z) and a node set' % version,
                     '%d segments' % len(segments))
        check_deck(deck_around(include, [5]), 'Gmsh %s' % version, len(x), len(tets),
                   {5: RHO * 6.0 * 2.0 * 2.0})
    # the top as a rigid sheet of shells 0.5 thick (--shells 7)
    rc, text, include = convert(os.path.join(OUT, 'block_gmsh22.msh'), ['--shells', '7'])
    sheet = os.path.join(OUT, 'block_sheet.k')
    os.replace(include, sheet)
    checks.check(rc == 0 and '%d shells' % len(top) in text, 'Gmsh: --shells 7 makes the '
                 'physical surface shell elements', text[-400:])
    if rc == 0:
        check_deck(deck_around(sheet, [5], sheets={7: 0.5}), 'Gmsh --shells', len(x),
                   len(tets) + len(top), {5: RHO * 6.0 * 2.0 * 2.0, 7: RHO * 6.0 * 2.0 * 0.5})
    # the block runs (positive volumes, the include as written)
    deck = deck_around(os.path.join(OUT, 'block_gmsh41.k'), [5], end_time=1.0e-6)
    rc, text = run(deck, os.path.join(OUT, 'block_run'))
    checks.check(rc == 0, 'Gmsh block: a few explicit cycles run', text[-400:])


def abaqus_hexes():
    path = os.path.join(OUT, 'two_hexes.inp')
    x, hexes = box_hexes(2.0, 1.0, 1.0, 2, 1, 1)
    hexes = np.array(hexes)
    hexes[1] = hexes[1][[4, 5, 6, 7, 0, 1, 2, 3]]            # upside down
    lines = ['*HEADING', 'two hexahedra', '*NODE']
    lines += ['%d, %g, %g, %g' % (k + 1, *p) for k, p in enumerate(x)]
    lines += ['*ELEMENT, TYPE=C3D8, ELSET=LEFT', '1, ' + ', '.join(str(v + 1) for v in hexes[0]),
              '*ELEMENT, TYPE=C3D8, ELSET=RIGHT', '2, ' + ', '.join(str(v + 1) for v in hexes[1]),
              '*NSET, NSET=BASE', ', '.join(str(k + 1) for k in range(len(x)) if x[k, 2] == 0)]
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')
    rc, text, include = convert(path)
    print('    %s' % text.strip())
    checks.check(rc == 0 and '1 elements turned' in text and 'parts [1, 2]' in text,
                 'Abaqus: converted, ELSETs as parts 1 and 2, the upside-down hex turned',
                 text[-400:])
    if rc == 0:
        sets = include_sets(include)
        checks.check(any(k[0] == 'NODE' for k in sets), 'Abaqus: the NSET as a node set',
                     str(sets.keys()))
        check_deck(deck_around(include, [1, 2], elform=1), 'Abaqus', len(x), 2,
                   {1: RHO, 2: RHO})


def nastran_wedges():
    x, hexes = box_hexes(2.0, 2.0, 1.0, 2, 2, 1)
    wedges = []
    for h in hexes:
        wedges.append([h[0], h[1], h[2], h[4], h[5], h[6]])
        wedges.append([h[0], h[2], h[3], h[4], h[6], h[7]])
    wedges = np.array(wedges)
    wedges[1::2] = wedges[1::2][:, [3, 4, 5, 0, 1, 2]]    # half of them upside down
    path = os.path.join(OUT, 'wedges.bdf')
    meshio.write(path, meshio.Mesh(x, [('wedge', wedges)]), file_format='nastran')
    rc, text, include = convert(path)
    print('    %s' % text.strip())
    checks.check(rc == 0 and '%d elements turned' % (len(wedges) // 2) in text,
                 'Nastran: converted, the upside-down wedges turned', text[-400:])
    if rc == 0:
        check_deck(deck_around(include, [1], elform=1), 'Nastran wedges', len(x), len(wedges),
                   {1: RHO * 2.0 * 2.0 * 1.0})


def gmsh_2d():
    x = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]], dtype=float)
    triangles = np.array([[0, 1, 4], [0, 4, 3]])
    quads = np.array([[1, 2, 5, 4]])
    lines = np.array([[0, 1], [1, 2]])
    mesh = meshio.Mesh(x, [('triangle', triangles), ('quad', quads), ('line', lines)],
                       cell_data={'gmsh:physical': [np.full(2, 1), np.full(1, 2),
                                                    np.full(2, 3)],
                                  'gmsh:geometrical': [np.full(2, 1), np.full(1, 1),
                                                       np.full(2, 1)]},
                       field_data={'plate': np.array([1, 2]), 'base': np.array([3, 1])})
    path = os.path.join(OUT, 'plate2d.msh')
    meshio.write(path, mesh, file_format='gmsh22', binary=False)
    rc, text, include = convert(path)
    print('    %s' % text.strip())
    checks.check(rc == 0 and '3 shells' in text, '2D Gmsh: triangles and quadrilaterals as '
                 'shells', text[-400:])
    if rc == 0:
        sets = include_sets(include)
        checks.check(len(sets.get(('SEGMENT', 3), [])) == 2, '2D Gmsh: the physical curve as a '
                     'segment set of edges', str(sets.keys()))
        check_deck(deck_around(include, [1, 2], shells=True, rigid=(2,)), '2D Gmsh', len(x),
                   3, {1: RHO * 1.0, 2: RHO * 1.0})


checks.check(meshio is not None, 'python3-meshio is installed (make deps installs it)')
def first_model_guide():
    """doc/first_model.md's deck, verbatim, around a Gmsh 4.1 billet with the guide's groups
    (volume 1, top 2, bottom 3): --check accepts it; run to 20 us instead of 2 ms, the top has
    moved 1000 mm/s x 20 us = 0.02 mm down and the bottom not at all."""
    doc = open(os.path.join(ROOT, 'doc', 'first_model.md')).read()
    deck = doc.split('<!-- first-model-deck -->')[1].split('```')[1].strip('\n')
    x, tets = box_tets(10.0, 10.0, 12.0, 4, 4, 5)
    tets = np.array(tets)
    path = os.path.join(OUT, 'billet.msh')
    write_gmsh41(path, x, tets, (1, 'billet'),
                 [(2, 'top', plane_faces(x, tets, 2, 12.0, +1)),
                  (3, 'bottom', plane_faces(x, tets, 2, 0.0, -1))])
    rc, text, include = convert(path)
    checks.check(rc == 0, 'guide: the billet converted', text[-400:])
    deck_path = os.path.join(OUT, 'upset.k')
    with open(deck_path, 'w') as f:
        f.write(deck + '\n')
    check_deck(deck_path, 'guide', len(x), len(tets), {1: RHO * 10.0 * 10.0 * 12.0})
    end = '    2.0e-3'
    checks.check(end in deck.splitlines(), 'guide: the deck ends at 2 ms', '')
    short = os.path.join(OUT, 'upset_short.k')
    with open(short, 'w') as f:
        f.write('\n'.join('    2.0e-5' if line == end else line for line in deck.splitlines()))
    rc, text = run(short, os.path.join(OUT, 'upset'))
    checks.check(rc == 0, 'guide: the deck runs', text[-400:])
    if rc == 0:
        h5 = os.path.join(OUT, 'upset', 'upset_short.h5')
        import h5py
        with h5py.File(h5, 'r') as f:
            last = sorted(f['states'])[-1]
            u = f['states/%s/point/displacement' % last][()]
            t = f['states/%s' % last].attrs.get('time')
        z = x[:, 2]
        top_u, bottom_u = u[abs(z - 12.0) < 1e-9, 2], u[abs(z) < 1e-9]
        want = -1000.0 * float(t)
        checks.check(np.allclose(top_u, want, rtol=1e-9) and np.all(bottom_u == 0.0) and
                     float(t) > 1.9e-5, 'guide: the top moved %.4g mm (1000 mm/s x %.3g s), the '
                     'bottom held' % (want, float(t)), 'top %s, bottom max %g' % (
                         top_u[:3], abs(bottom_u).max()))


def tet_volumes(x, tets):
    d = np.stack([x[tets[:, k]] - x[tets[:, 0]] for k in (1, 2, 3)], axis=2)
    return np.linalg.det(d) / 6.0


def gmsh_cylinder_and_mixed():
    """Gmsh 2.2 meshes (meshio; its 4.1 writer drops the physical groups) of the kinds Gmsh
    makes: a cylinder of tetrahedra (a box of 6 x
    6 x 4 cubes of 6 tets mapped onto the disk of radius 5, height 8) and a mixed mesh, a block
    of hexahedra (physical volume 1) beside a block of tetrahedra (physical volume 2) sharing
    the nodes of their common face."""
    x, tets = box_tets(2.0, 2.0, 8.0, 6, 6, 4)
    tets = np.array(tets)
    u, v = x[:, 0] - 1.0, x[:, 1] - 1.0             # the square [-1, 1]^2 onto the unit disk
    x = np.column_stack([5.0 * u * np.sqrt(1 - v * v / 2), 5.0 * v * np.sqrt(1 - u * u / 2),
                         x[:, 2]])
    volume = abs(tet_volumes(x, tets)).sum()
    path = os.path.join(OUT, 'cylinder_gmsh22.msh')
    meshio.write(path, meshio.Mesh(x, [('tetra', tets)],
                                   cell_data={'gmsh:physical': [np.full(len(tets), 3)],
                                              'gmsh:geometrical': [np.full(len(tets), 1)]},
                                   field_data={'cylinder': np.array([3, 3])}),
                 file_format='gmsh22', binary=False)
    rc, text, include = convert(path)
    checks.check(rc == 0, 'Gmsh cylinder: converted', text[-400:])
    if rc == 0:
        print('    cylinder: %d tets, volume %.6f mm^3 (pi r^2 h = %.6f)' % (
            len(tets), volume, np.pi * 25.0 * 8.0))
        check_deck(deck_around(include, [3]), 'Gmsh cylinder', len(x), len(tets),
                   {3: RHO * volume})
    xh, hexes = box_hexes(2.0, 2.0, 2.0, 2, 2, 2)
    xt, tets = box_tets(2.0, 2.0, 2.0, 2, 2, 2)
    xt = xt + [2.0, 0.0, 0.0]
    merged = {tuple(np.round(p, 9)): k for k, p in enumerate(xh)}
    index = []
    extra = []
    for p in xt:
        key = tuple(np.round(p, 9))
        if key not in merged:
            merged[key] = len(xh) + len(extra)
            extra.append(p)
        index.append(merged[key])
    x = np.vstack([xh, extra])
    tets = np.array(index)[np.array(tets)]
    hexes = np.array(hexes)
    path = os.path.join(OUT, 'mixed_gmsh22.msh')
    meshio.write(path, meshio.Mesh(x, [('hexahedron', hexes), ('tetra', tets)],
                                   cell_data={'gmsh:physical': [np.full(len(hexes), 1),
                                                                np.full(len(tets), 2)],
                                              'gmsh:geometrical': [np.full(len(hexes), 1),
                                                                   np.full(len(tets), 2)]},
                                   field_data={'hexes': np.array([1, 3]),
                                               'tets': np.array([2, 3])}),
                 file_format='gmsh22', binary=False)
    rc, text, include = convert(path)
    checks.check(rc == 0, 'Gmsh mixed hexahedra and tetrahedra: converted', text[-400:])
    if rc == 0:
        check_deck(deck_around(include, [1, 2], elforms={1: 1, 2: 10}), 'Gmsh mixed', len(x),
                   len(hexes) + len(tets), {1: RHO * 8.0, 2: RHO * 8.0})


if meshio is not None:
    first_model_guide()
    gmsh_cylinder_and_mixed()
    gmsh_block()
    abaqus_hexes()
    nastran_wedges()
    gmsh_2d()
checks.exit()
