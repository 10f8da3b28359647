"""Rigid bodies moved along and about a vector: *BOUNDARY_PRESCRIBED_MOTION_RIGID DOF 4 / -4
(translation along *DEFINE_VECTOR VID; -4: no motion across it) and 8 / -8 (rotation about
VID; -8: no other rotation), explicit (doc/keywords.md 3.8; mm, t, s, N, MPa). A rigid box
1 x 2 x 3 mm of hexahedra, DTINIT 0.1 us, 100 us:

1. DOF 4 along (3, 4, 0)/5 at 1 m/s (VAD 0), and the same as a displacement curve (VAD 2):
   every node moves by v T n (1e-9), as with DOF 1 and 2 at 0.6 v and 0.8 v.
2. Under a body load along z: DOF 4 along x leaves the box free to fall (a T^2/2, 1e-6); -4
   holds it on the line (0).
3. DOF 8 about z at 100 rad/s: the same displacements as DOF 7 (1e-12 of the size).
4. -8 about (1, 0, 1)/sqrt(2) on the box, and 8 about it on a cube (whose inertia leaves no
   other rotation): every node where Rodrigues' rotation by omega T puts it (1e-9).
5. *DEFINE_VECTOR_NODES (from node to node) gives the bits of the same *DEFINE_VECTOR; an
   undefined node is an error at its card.
6. DOF 4 across an axis held by CON1: an error naming the conflict.
"""
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(__file__))
from deck_writer import Checks, f10, free, nodes_card, elements_card
from explicit_cases import DENSITY, YOUNG, POISSON, box_hexes, curve, run_case

checks = Checks('rigid_vector_motion')
T, V, OMEGA, A_BODY = 1.0e-4, 1000.0, 100.0, 1.0e7


def run_box(name, motions, vector=(3.0, 4.0, 0.0), size=(1.0, 2.0, 3.0), extra=(),
            constraints=f10(0.0, 0, 0), expect_ok=True):
    """The rigid box with the given motion cards; returns (x0, final displacement) or the
    run's text when it is refused."""
    x, conn = box_hexes(size[0], size[1], size[2], 1, 2, 3)
    x = x - 0.5 * np.array(size)                      # centred on the origin
    blocks = [nodes_card(x), elements_card('ELEMENT_SOLID', conn),
              ['*PART', 'box', f10(1, 1, 1), '*SECTION_SOLID', f10(1, 1),
               '*MAT_RIGID', free(1, DENSITY, YOUNG, POISSON), constraints],
              ['*DEFINE_VECTOR', f10(7, 0.0, 0.0, 0.0, *vector)],
              curve(1, [(0.0, 1.0), (1.0, 1.0)]),
              curve(2, [(0.0, 0.0), (T, V * T), (2 * T, 2 * V * T)]),
              ['*BOUNDARY_PRESCRIBED_MOTION_RIGID'] + motions,
              ['*CONTROL_TERMINATION', f10(T), '*CONTROL_TIMESTEP', f10(1.0e-7),
               '*DATABASE_BINARY_D3PLOT', f10(T)]] + list(extra)
    rc, text, out = run_case('rigid_vector_' + name, blocks)
    checks.check((rc == 0) == expect_ok, name + ': run %s' % ('succeeds' if expect_ok else
                                                               'is refused'), text[-500:])
    if rc != 0:
        return text
    with h5py.File(os.path.join(out, 'rigid_vector_%s.h5' % name)) as f:
        order = np.argsort(f['mesh/node_ids'][()])
        last = sorted(f['states'])[-1]
        return x, f['states/%s/point/displacement' % last][()][order]


def rodrigues(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


n = np.array([0.6, 0.8, 0.0])                   # the default vector (3, 4, 0)/5
x, u4 = run_box('dof4', [f10(1, 4, 0, 1, V, 7)])
_, u4d = run_box('dof4_vad2', [f10(1, 4, 2, 2, 1.0, 7)])
_, u12 = run_box('dof12', [f10(1, 1, 0, 1, 0.6 * V), f10(1, 2, 0, 1, 0.8 * V)])
want = V * T * n
err4 = np.abs(u4 - want).max() / (V * T)
err4d = np.abs(u4d - want).max() / (V * T)
err12 = np.abs(u4 - u12).max() / (V * T)
print('    DOF 4 along (3,4,0): |u - v T n| / v T = %.1e (VAD 0), %.1e (VAD 2); against DOF 1 + 2: '
      '%.1e' % (err4, err4d, err12))
checks.check(err4 < 1e-9 and err4d < 1e-9 and err12 < 1e-9, 'DOF 4: every node moves by v T '
             'along the vector (velocity and displacement curves; as DOF 1 and 2 together)',
             '%.1e %.1e %.1e' % (err4, err4d, err12))

load = [['*LOAD_BODY_Z', f10(1, A_BODY)]]
_, uf = run_box('dof4_falls', [f10(1, 4, 0, 1, V, 7)], vector=(1.0, 0.0, 0.0), extra=load)
_, uh = run_box('dof-4_held', [f10(1, -4, 0, 1, V, 7)], vector=(1.0, 0.0, 0.0), extra=load)
fall = 0.5 * A_BODY * T ** 2
print('    body load along z: |u_z| %.6e mm with DOF 4 (a T^2/2 = %.6e), %.1e with -4'
      % (np.abs(uf[:, 2]).mean(), fall, np.abs(uh[:, 2]).max()))
checks.check(np.all(abs(abs(uf[:, 2]) / fall - 1) < 1e-6) and np.allclose(uf[:, 0], V * T,
                                                                         rtol=1e-9),
             'DOF 4: free across the vector (falls by a T^2/2 under the body load)',
             '%s' % uf[:3])
checks.check(np.abs(uh[:, 2]).max() == 0.0 and np.allclose(uh[:, 0], V * T, rtol=1e-9),
             'DOF -4: held on the line (no fall)', '%s' % uh[:3])

_, u8z = run_box('dof8_z', [f10(1, 8, 0, 1, OMEGA, 7)], vector=(0.0, 0.0, 1.0))
_, u7 = run_box('dof7', [f10(1, 7, 0, 1, OMEGA)])
err87 = np.abs(u8z - u7).max() / 3.0
print('    DOF 8 about z against DOF 7: %.1e of the size' % err87)
checks.check(err87 < 1e-12 and np.abs(u7).max() > 1e-3, 'DOF 8 about z: the displacements of '
             'DOF 7', '%.1e' % err87)

axis = (1.0, 0.0, 1.0)
rot = rodrigues(axis, 10 * OMEGA * T)
for name, dof, size in (('dof-8_box', -8, (1.0, 2.0, 3.0)), ('dof8_cube', 8, (2.0, 2.0, 2.0))):
    out = run_box(name, [f10(1, dof, 0, 1, 10 * OMEGA, 7)], vector=axis, size=size)
    if isinstance(out, str):
        continue
    x0, u = out
    want = x0 @ rot.T - x0
    err = np.abs(u - want).max() / max(size)
    print('    DOF %d about (1,0,1), %.2f rad: |u - Rodrigues| / size = %.1e' % (dof, 10 * OMEGA
                                                                                   * T, err))
    checks.check(err < 1e-9, 'DOF %d about a tilted vector: every node where Rodrigues\' '
                 'rotation puts it (%s)' % (dof, name), '%.1e' % err)

# *DEFINE_VECTOR_NODES: from node 1 (the corner -0.5, -1, -1.5) to the node at (0.5, 1, -1.5)
# of the box's grid, (1, 2, 0): the bits of *DEFINE_VECTOR (1, 2, 0)
xg, _ = box_hexes(1.0, 2.0, 3.0, 1, 2, 3)
head = int(np.nonzero((xg[:, 0] == 1.0) & (xg[:, 1] == 2.0) & (xg[:, 2] == 0.0))[0][0]) + 1
by_nodes = [['*DEFINE_VECTOR_NODES', f10(8, 1, head)]]
_, un = run_box('vector_nodes', [f10(1, 4, 0, 1, V, 8)], extra=by_nodes)
_, uv = run_box('vector_12', [f10(1, 4, 0, 1, V, 7)], vector=(1.0, 2.0, 0.0))
checks.check(np.array_equal(un, uv) and np.abs(un).max() > 0.0, '*DEFINE_VECTOR_NODES: DOF 4 '
             'along it gives the bits of the same *DEFINE_VECTOR')
text = run_box('vector_nodes_bad', [f10(1, 4, 0, 1, V, 8)],
               extra=[['*DEFINE_VECTOR_NODES', f10(8, 1, 999)]], expect_ok=False)
checks.check(isinstance(text, str) and 'node 999 (NODEH) is not defined' in text,
             '*DEFINE_VECTOR_NODES with an undefined node: an error at its card', str(text)[-300:])
text = run_box('dof4_held_x', [f10(1, 4, 0, 1, V, 7)], constraints=f10(1.0, 1, 0),
               expect_ok=False)
checks.check(isinstance(text, str) and 'has a component along a translation that is held' in
             text, 'DOF 4 across a held axis: an error names the conflict', str(text)[-300:])
checks.exit()
