#!/usr/bin/python3
"""Write an XDMF 3 file beside a mefem HDF5 result, so that ParaView ("Xdmf3 Reader") and VisIt
open the HDF5 data directly, every state a time step.

    python3 post/h5_to_xdmf.py results/deck/deck.h5            # writes results/deck/deck.xdmf

The XDMF file only points into the HDF5 file (doc/hdf5_layout.md): the reference coordinates,
one mixed topology and, per state, its time and every point and cell field (ncomp 1: Scalar,
3: Vector, 6: Tensor6 in mefem's order xx yy zz xy yz zx, 9: Tensor, else Matrix). XDMF's
mixed topology lists each cell as its XDMF type code and its nodes (a line also its node
count): mefem writes it as /mesh/xdmf_topology, and its own .xdmf file beside the result
(src/io/xdmf_output.f90); for a file written before it did, this script adds the dataset (the
file opened for appending, its other data untouched). The cells' node order is
VTK's, which XDMF's linear cells share.
"""
import argparse
import os
import sys

import h5py
import numpy as np

# VTK cell type -> XDMF mixed-topology code (line: followed by its node count)
VTK_TO_XDMF = {3: 2, 5: 4, 9: 5, 10: 6, 14: 7, 13: 8, 12: 9}
ATTRIBUTE_TYPE = {1: 'Scalar', 3: 'Vector', 6: 'Tensor6', 9: 'Tensor'}


def mixed_topology(types, offsets, connectivity):
    """The XDMF mixed topology array: per cell its code (a line: and 2), then its nodes."""
    parts = []
    for c, vtk_type in enumerate(types):
        if int(vtk_type) not in VTK_TO_XDMF:
            raise SystemExit('h5_to_xdmf: cell %d has VTK type %d, which has no XDMF code here'
                             % (c, vtk_type))
        code = [VTK_TO_XDMF[int(vtk_type)]]
        nodes = connectivity[offsets[c]:offsets[c + 1]]
        if vtk_type == 3:
            code.append(len(nodes))
        parts.append(np.concatenate([code, nodes]))
    return np.concatenate(parts).astype(np.int64) if parts else np.zeros(0, np.int64)


def data_item(h5name, path, shape, number_type, precision):
    dims = ' '.join(str(d) for d in shape)
    return ('<DataItem Dimensions="%s" NumberType="%s" Precision="%d" Format="HDF">%s:%s'
            '</DataItem>' % (dims, number_type, precision, h5name, path))


def write_xdmf(h5path, xdmf_path):
    """Add /mesh/xdmf_topology to the HDF5 file (once) and write the XDMF file."""
    with h5py.File(h5path, 'r+') as f:
        mesh = f['mesh']
        if 'xdmf_topology' not in mesh:
            mesh.create_dataset('xdmf_topology', data=mixed_topology(
                mesh['cell_types'][()], mesh['cell_offsets'][()], mesh['connectivity'][()]))
        nnode = mesh['coordinates'].shape[0]
        ncell = mesh['cell_types'].shape[0]
        ntopology = mesh['xdmf_topology'].shape[0]
        states = [(k, float(f['states'][k].attrs['time']),
                   [(kind, name, f['states'][k][kind][name].shape)
                    for kind in ('point', 'cell') for name in sorted(f['states'][k][kind])])
                  for k in sorted(f['states'])]
    h5name = os.path.relpath(h5path, os.path.dirname(os.path.abspath(xdmf_path)))
    lines = ['<?xml version="1.0" ?>', '<Xdmf Version="3.0">', '  <Domain>',
             '    <Grid Name="mefem" GridType="Collection" CollectionType="Temporal">']
    for key, time, fields in states:
        lines += ['      <Grid Name="state %s" GridType="Uniform">' % key,
                  '        <Time Value="%.17g"/>' % time,
                  '        <Topology TopologyType="Mixed" NumberOfElements="%d">' % ncell,
                  '          ' + data_item(h5name, '/mesh/xdmf_topology', (ntopology,), 'Int', 8),
                  '        </Topology>',
                  '        <Geometry GeometryType="XYZ">',
                  '          ' + data_item(h5name, '/mesh/coordinates', (nnode, 3), 'Float', 8),
                  '        </Geometry>']
        for kind, name, shape in fields:
            ncomp = shape[1] if len(shape) > 1 else 1
            lines += ['        <Attribute Name="%s" AttributeType="%s" Center="%s">'
                      % (name, ATTRIBUTE_TYPE.get(ncomp, 'Matrix'),
                         'Node' if kind == 'point' else 'Cell'),
                      '          ' + data_item(h5name, '/states/%s/%s/%s' % (key, kind, name),
                                               shape, 'Float', 8),
                      '        </Attribute>']
        lines.append('      </Grid>')
    lines += ['    </Grid>', '  </Domain>', '</Xdmf>']
    with open(xdmf_path, 'w') as out:
        out.write('\n'.join(lines) + '\n')
    return len(states)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('h5', help='mefem HDF5 result (results/<deck>/<deck>.h5)')
    parser.add_argument('-o', '--output', help='XDMF file (default: beside the .h5)')
    args = parser.parse_args(argv)
    if not os.path.isfile(args.h5):
        raise SystemExit('h5_to_xdmf: %s: no such file' % args.h5)
    xdmf_path = args.output or os.path.splitext(args.h5)[0] + '.xdmf'
    n = write_xdmf(args.h5, xdmf_path)
    print('h5_to_xdmf: %s: %d states (open it in ParaView with the Xdmf3 reader)'
          % (xdmf_path, n))


if __name__ == '__main__':
    main(sys.argv[1:])
