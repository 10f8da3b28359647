#!/usr/bin/python3
"""Write an LS-DYNA keyword deck of a structured block of linear tetrahedra or hexahedra
(reader and explicit benchmarks).

The block [0, nx*h] x [0, ny*h] x [0, nz*h] is divided into nx*ny*nz hexahedral cells, each
split into 5 tetrahedra (alternating by cell parity so that the face diagonals of neighbouring
cells match) or 6 (Kuhn split along the cell diagonal, the same in every cell), or kept as one
hexahedron (--tets 1, LS-DYNA's node order). Every tet is
positively oriented: N1-N2-N3 counter-clockwise seen from N4 (det[N2-N1, N3-N1, N4-N1] > 0).

The deck has *KEYWORD, *TITLE, *PART, *SECTION_SOLID (ELFORM=43), *MAT_ELASTIC (aluminium,
mm-s-tonne-N-MPa), *NODE in fixed format (I8, 3 x E16) and *ELEMENT_SOLID in the current
two-line layout (EID PID / N1..N8) or the legacy one-line layout (EID PID N1..N8), and *END.

Formatting is vectorised (integers are turned into digit bytes with numpy; coordinates are
formatted in large chunks), so a deck of 6 million lines is written in a few seconds.

usage: generate_block_deck.py NX NY NZ OUTPUT.k [--tets 5|6|1] [--layout current|legacy]
                              [--size H] [--id-offset K]
"""
import argparse
import os
import sys
import time

import numpy as np

#: Corners of the unit cell as (a, b, c) offsets; local corner index = a + 2*b + 4*c.
CORNERS = np.array([[a, b, c] for c in (0, 1) for b in (0, 1) for a in (0, 1)])


def _corner(a, b, c):
    return a + 2 * b + 4 * c


def _orient(tets):
    """Reorder each local tet (rows of corner indices) so that its volume is positive."""
    out = []
    for t in tets:
        p = CORNERS[list(t)].astype(float)
        det = np.linalg.det(np.array([p[1] - p[0], p[2] - p[0], p[3] - p[0]]))
        if abs(det) < 1e-12:
            raise ValueError(f'degenerate template tet {t}')
        out.append(list(t) if det > 0 else [t[0], t[2], t[1], t[3]])
    return np.array(out, dtype=np.int64)


def templates(n_tets):
    """Local tets of a cell: (template for even cells, template for odd cells)."""
    if n_tets == 6:
        # Kuhn split: paths 000 -> e_p -> e_p + e_q -> 111 for every axis order (p, q, r)
        tets = []
        for order in ([0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]):
            pos = [0, 0, 0]
            path = [_corner(*pos)]
            for axis in order:
                pos[axis] = 1
                path.append(_corner(*pos))
            tets.append(path)
        t = _orient(tets)
        return t, t
    if n_tets != 5:
        raise ValueError('--tets must be 5 or 6')

    def five(central):
        """Central tet on the corners of one parity, one corner tet at each other corner."""
        centre = [k for k in range(8) if CORNERS[k].sum() % 2 == central]
        tets = [centre]
        for k in range(8):
            if CORNERS[k].sum() % 2 != central:
                nbrs = [m for m in centre if np.abs(CORNERS[m] - CORNERS[k]).sum() == 1]
                tets.append([k] + nbrs)
        return _orient(tets)

    # global corner parity = cell parity + local parity: central tets always join the
    # globally even nodes, so the diagonals of a shared face agree
    return five(0), five(1)


def block_mesh(nx, ny, nz, n_tets, h, id_offset):
    """Node ids, coordinates (n, 3) and tet connectivity (ids, (m, 4)) of the block."""
    i, j, k = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1), np.arange(nz + 1),
                          indexing='ij')
    i, j, k = (a.transpose(2, 1, 0).ravel() for a in (i, j, k))   # i fastest
    coords = np.column_stack([i, j, k]).astype(np.float64) * h
    node_ids = np.arange(1, coords.shape[0] + 1, dtype=np.int64) + id_offset

    ci, cj, ck = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing='ij')
    ci, cj, ck = (a.transpose(2, 1, 0).ravel() for a in (ci, cj, ck))
    base = ci + (nx + 1) * (cj + (ny + 1) * ck)                   # node index of corner 000
    offsets = CORNERS[:, 0] + (nx + 1) * (CORNERS[:, 1] + (ny + 1) * CORNERS[:, 2])
    cell_nodes = base[:, None] + offsets[None, :]                # (cells, 8) node indices
    if n_tets == 1:                    # hexahedra: LS-DYNA's order (bottom 00 10 11 01, top)
        return node_ids, coords, node_ids[cell_nodes[:, [0, 1, 3, 2, 4, 5, 7, 6]]]
    even, odd = templates(n_tets)
    parity = (ci + cj + ck) % 2
    conn = np.where(parity[:, None, None] == 0,
                    cell_nodes[:, even], cell_nodes[:, odd])     # (cells, n_tets, 4)
    conn = conn.reshape(-1, 4)
    return node_ids, coords, node_ids[conn]


def int_columns(values, width):
    """Right-aligned fixed-width decimal text of non-negative integers, as bytes (rows, cols*w)."""
    values = np.asarray(values, dtype=np.int64)
    if values.size and values.min() < 0:
        raise ValueError('negative integers are not formatted here')
    if values.size and values.max() >= 10 ** width:
        raise ValueError(f'integer {values.max()} does not fit in {width} columns')
    rows, cols = values.shape
    out = np.full((rows, cols, width), ord(' '), dtype=np.uint8)
    v = values.copy()
    for pos in range(width - 1, -1, -1):
        digit = (v % 10).astype(np.uint8) + ord('0')
        show = (v > 0) | (pos == width - 1)
        out[:, :, pos] = np.where(show, digit, out[:, :, pos])
        v //= 10
    return out.reshape(rows, cols * width)


def lines_bytes(parts):
    """Join byte blocks (rows, w_i) side by side and end every row with a line feed."""
    rows = parts[0].shape[0]
    newline = np.full((rows, 1), ord('\n'), dtype=np.uint8)
    return np.hstack(list(parts) + [newline]).tobytes()


def write_nodes(f, node_ids, coords, chunk=200000):
    """*NODE cards: NID (I8), X Y Z (E16)."""
    f.write(b'*NODE\n$#   nid               x               y               z\n')
    for s in range(0, len(node_ids), chunk):
        ids = int_columns(node_ids[s:s + chunk, None], 8)
        xyz = coords[s:s + chunk]
        text = ('%16.9e%16.9e%16.9e\n' * xyz.shape[0]) % tuple(xyz.ravel().tolist())
        xyz_bytes = np.frombuffer(text.encode('ascii'), dtype=np.uint8).reshape(-1, 49)
        f.write(lines_bytes([ids, xyz_bytes[:, :48]]))


def write_elements(f, conn, pid, layout, first_id, chunk=500000):
    """*ELEMENT_SOLID cards of tets (N5..N8 = N4) or hexahedra, in the current or legacy
    layout."""
    f.write(b'*ELEMENT_SOLID\n')
    if layout == 'current':
        f.write(b'$#   eid     pid\n$#    n1      n2      n3      n4      n5      n6      n7'
                b'      n8\n')
    else:
        f.write(b'$#   eid     pid      n1      n2      n3      n4      n5      n6      n7'
                b'      n8\n')
    for s in range(0, conn.shape[0], chunk):
        c = conn[s:s + chunk]
        m = c.shape[0]
        eids = np.arange(s, s + m, dtype=np.int64)[:, None] + first_id
        head = int_columns(np.hstack([eids, np.full((m, 1), pid, dtype=np.int64)]), 8)
        nodes = int_columns(c if c.shape[1] == 8 else
                            np.hstack([c, np.repeat(c[:, 3:4], 4, axis=1)]), 8)
        if layout == 'current':
            nl = np.full((m, 1), ord('\n'), dtype=np.uint8)
            f.write(lines_bytes([head, nl, nodes]))
        else:
            f.write(lines_bytes([head, nodes]))


def write_deck(path, nx, ny, nz, n_tets=5, layout='current', h=1.0, id_offset=0):
    """Write the deck; returns (nodes, elements, lines written)."""
    node_ids, coords, conn = block_mesh(nx, ny, nz, n_tets, h, id_offset)
    header = (
        '*KEYWORD\n'
        '$ mefem reader benchmark: structured block of linear tetrahedra\n'
        f'$ cells {nx} x {ny} x {nz}, {n_tets} tets per cell, {layout} *ELEMENT_SOLID layout\n'
        '$ units: mm, s, tonne, N, MPa\n'
        '*TITLE\n'
        f'block {nx}x{ny}x{nz} x{n_tets} tets\n'
        '*PART\n'
        'block\n'
        '$#     pid     secid       mid\n'
        '         1         1         1\n'
        '*SECTION_SOLID\n'
        '$#   secid    elform\n'
        '         1        43\n'
        '*MAT_ELASTIC\n'
        '$#     mid        ro         e        pr\n'
        '         1   2.70E-9   70000.0       0.3\n')
    tmp = path + '.partial'
    with open(tmp, 'wb') as f:
        f.write(header.encode('ascii'))
        write_nodes(f, node_ids, coords)
        write_elements(f, conn, 1, layout, 1 + id_offset)
        f.write(b'*END\n')
    os.replace(tmp, path)
    with open(path, 'rb') as f:
        n_lines = sum(block.count(b'\n') for block in iter(lambda: f.read(1 << 24), b''))
    return len(node_ids), conn.shape[0], n_lines


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('nx', type=int)
    ap.add_argument('ny', type=int)
    ap.add_argument('nz', type=int)
    ap.add_argument('output')
    ap.add_argument('--tets', type=int, default=5, choices=(5, 6, 1),
                    help='tets per cell (1: the cells as hexahedra)')
    ap.add_argument('--layout', default='current', choices=('current', 'legacy'),
                    help='*ELEMENT_SOLID layout: two lines (current) or one line (legacy)')
    ap.add_argument('--size', type=float, default=1.0, help='cell edge length (mm)')
    ap.add_argument('--id-offset', type=int, default=0,
                    help='added to every node and element id (to exercise wide ids)')
    args = ap.parse_args(argv)
    if min(args.nx, args.ny, args.nz) < 1:
        ap.error('cell counts must be >= 1')
    t0 = time.time()
    n_nodes, n_elems, n_lines = write_deck(args.output, args.nx, args.ny, args.nz, args.tets,
                                           args.layout, args.size, args.id_offset)
    size_mb = os.path.getsize(args.output) / 1e6
    print(f'{args.output}: {n_nodes} nodes, {n_elems} tets, {n_lines} lines, '
          f'{size_mb:.1f} MB, written in {time.time() - t0:.1f} s')


if __name__ == '__main__':
    main(sys.argv[1:])
