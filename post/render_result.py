#!/usr/bin/python3
"""Render a mefem result as a PNG picture of the deformed model coloured by a field, by one
command and without a display (matplotlib's Agg backend: works on a cluster's login node or in
a batch job, no ParaView, no X server).

Reads the HDF5 result file (doc/hdf5_layout.md): the mesh, the chosen state's displacement
(added to the coordinates, times --scale) and a point or cell field. 3D models are drawn by
their outer surface (the faces of tetrahedra, wedges and hexahedra that belong to one cell
only, plus shells), 2D models (plane strain, z = 0) by their cells in the x-y plane. A vector
or tensor field is shown by its magnitude (a symmetric tensor's Voigt components: its von Mises
value is usually the field to pick instead, `von_mises`). Faces take the mean of their nodes'
values (point fields) or their cell's value (cell fields).

usage: /usr/bin/python3 post/render_result.py RESULT.h5 [--field von_mises] [--state -1]
           [--scale 1] [--view ELEV AZIM] [--out PICTURE.png] [--size 8 6]
  --field   point or cell field of the state (default von_mises, else the first there is);
            --field list prints the state's fields
  --state   state number as written (0, 1, ...), negative counts from the last (default -1)
  --scale   displacement magnification (default 1: the true deformed shape)
  --view    3D camera elevation and azimuth in degrees (default 25 -60)
  --out     picture file (default RESULT_<field>_<state>.png beside the result)
Units are those of the deck (the colour bar names the field, not a unit).

Test: tests/output/test_render_result.py (an explicit run rendered; the picture's size, that it
is not blank, and the colours of two faces of known value).
"""
import argparse
import os
import sys

import numpy as np
import h5py
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

# faces of the VTK solid cells as node positions within the cell (mefem's corner order, the
# VTK one): tetra 10, wedge 13, hexahedron 12
SOLID_FACES = {
    10: [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)],
    13: [(0, 1, 2), (3, 5, 4), (0, 3, 4, 1), (1, 4, 5, 2), (0, 2, 5, 3)],
    12: [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (0, 4, 7, 3)],
}
SURFACE_CELLS = (5, 9)          # triangles and quadrilaterals: drawn as they are


def read_result(path, state):
    """Mesh arrays, the state's group name, time and point and cell fields (dicts)."""
    with h5py.File(path, 'r') as f:
        mesh = {k: f['mesh/' + k][()] for k in ('coordinates', 'cell_types', 'cell_offsets',
                                                 'connectivity')}
        names = sorted(f['states'].keys())
        key = names[state]
        g = f['states/' + key]
        point = {k: g['point/' + k][()] for k in g['point']}
        cell = {k: g['cell/' + k][()] for k in g['cell']}
        return mesh, key, float(g.attrs['time']), point, cell


def scalar(values):
    """A field's values as one number per row: the value itself or the magnitude."""
    values = np.asarray(values, dtype=float)
    if values.ndim == 1 or values.shape[1] == 1:
        return values.reshape(-1)
    return np.linalg.norm(values, axis=1)


def surface_faces(mesh):
    """(faces as node-row tuples, the cell of each face) of the model's surface: the faces of
    solid cells that belong to one cell only, and every triangle or quadrilateral cell."""
    types, offsets, conn = mesh['cell_types'], mesh['cell_offsets'], mesh['connectivity']
    seen = {}
    faces, owners = [], []
    for c, kind in enumerate(types):
        nodes = conn[offsets[c]:offsets[c + 1]]
        if kind in SOLID_FACES:
            for local in SOLID_FACES[kind]:
                face = tuple(int(nodes[i]) for i in local)
                key = tuple(sorted(set(face)))
                if len(key) < 3:
                    continue              # a degenerate face (collapsed hexahedron)
                if key in seen:
                    seen[key] = None      # shared by two cells: inside
                else:
                    seen[key] = (face, c)
        elif kind in SURFACE_CELLS:
            faces.append(tuple(int(n) for n in nodes))
            owners.append(c)
    for entry in seen.values():
        if entry is not None:
            faces.append(entry[0])
            owners.append(entry[1])
    return faces, np.array(owners, dtype=int)


def face_values(faces, owners, field, on_cells):
    """One value per face: the cell's (cell field) or the mean of its nodes' (point field)."""
    if on_cells:
        return field[owners]
    return np.array([field[list(face)].mean() for face in faces])


def render(path, field_name='von_mises', state=-1, scale=1.0, view=(25.0, -60.0), out=None,
           size=(8.0, 6.0)):
    """Write the picture; returns its path and the (min, max) of the values drawn."""
    mesh, key, time, point, cell = read_result(path, state)
    if field_name == 'list':
        print('state %s (t = %g): point fields %s; cell fields %s' % (
            key, time, ', '.join(sorted(point)), ', '.join(sorted(cell))))
        return None, None
    if field_name not in point and field_name not in cell:
        available = sorted(point) + sorted(cell)
        if field_name != 'von_mises' or not available:
            sys.exit('render_result: state %s has no field "%s" (it has: %s)' % (
                key, field_name, ', '.join(available) or 'none'))
        field_name = available[0]
    on_cells = field_name not in point
    field = scalar(cell[field_name] if on_cells else point[field_name])
    x = mesh['coordinates'].astype(float).copy()
    if 'displacement' in point:
        x += scale * point['displacement'][:, :3]
    faces, owners = surface_faces(mesh)
    values = face_values(faces, owners, field, on_cells)
    low, high = float(values.min()), float(values.max())
    norm = matplotlib.colors.Normalize(vmin=low, vmax=high if high > low else low + 1.0)
    colours = plt.get_cmap('viridis')(norm(values))
    planar = np.allclose(mesh['coordinates'][:, 2], 0.0)
    fig = plt.figure(figsize=size)
    if planar:
        ax = fig.add_subplot(1, 1, 1)
        polys = PolyCollection([x[list(face), :2] for face in faces], facecolors=colours,
                               edgecolors='k', linewidths=0.1)
        ax.add_collection(polys)
        ax.set_xlim(x[:, 0].min(), x[:, 0].max())
        ax.set_ylim(x[:, 1].min(), x[:, 1].max())
        ax.set_aspect('equal')
        ax.set_xlabel('x')
        ax.set_ylabel('y')
    else:
        ax = fig.add_subplot(1, 1, 1, projection='3d')
        polys = Poly3DCollection([x[list(face)] for face in faces], facecolors=colours,
                                 edgecolors='k', linewidths=0.05)
        ax.add_collection3d(polys)
        lo, hi = x.min(axis=0), x.max(axis=0)
        centre, half = (lo + hi) / 2, (hi - lo).max() / 2
        for axis, set_lim in enumerate((ax.set_xlim, ax.set_ylim, ax.set_zlim)):
            set_lim(centre[axis] - half, centre[axis] + half)
        ax.set_box_aspect((1, 1, 1))
        ax.view_init(elev=view[0], azim=view[1])
        ax.set_xlabel('x')
        ax.set_ylabel('y')
        ax.set_zlabel('z')
    mappable = matplotlib.cm.ScalarMappable(norm=norm, cmap='viridis')
    mappable.set_array(values)
    fig.colorbar(mappable, ax=ax, shrink=0.7, label=field_name + (' (cells)' if on_cells
                                                                   else ' (nodes)'))
    ax.set_title('%s, state %s, t = %g, displacement x %g' % (
        os.path.basename(path), key, time, scale))
    if out is None:
        out = os.path.splitext(path)[0] + '_%s_%s.png' % (field_name, key)
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out, (low, high)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('result', help='the HDF5 result file (results/<deck>/<deck>.h5)')
    parser.add_argument('--field', default='von_mises')
    parser.add_argument('--state', type=int, default=-1)
    parser.add_argument('--scale', type=float, default=1.0)
    parser.add_argument('--view', type=float, nargs=2, default=(25.0, -60.0))
    parser.add_argument('--out')
    parser.add_argument('--size', type=float, nargs=2, default=(8.0, 6.0))
    args = parser.parse_args()
    out, limits = render(args.result, args.field, args.state, args.scale, tuple(args.view),
                         args.out, tuple(args.size))
    if out:
        print('render_result: %s (%s from %g to %g)' % (out, args.field, limits[0], limits[1]))


if __name__ == '__main__':
    main()
