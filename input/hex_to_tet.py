#!/usr/bin/python3
"""Split the hexahedra of an LS-DYNA keyword deck into tetrahedra, so that a hex deck runs in
mefem (which has no deformable hexahedra yet) with ME-FEM (43) or nodal-pressure (13) tets.

Every 8-node hexahedron of *ELEMENT_SOLID (eight distinct nodes) gets one new node at its
centroid and becomes 12 tetrahedra: each of its six faces is cut into two triangles along the
diagonal through the face's lowest node id, and each triangle is joined to the centroid. Two
hexes that share a face cut it the same way (the rule depends on the face's nodes only), so the
tet mesh is conforming whatever the hex mesh; no new node is put on a face. Tets and other
solids written in the deck are kept. The new nodes are numbered after the largest node id,
the new tets after the largest element id (the first tet of a hex keeps the hex's id, so sets
of elements by id still find one of its tets). The sections of the parts whose hexes were
split get ELFORM --elform (43 by default). Everything else of the deck is copied unchanged;
*INCLUDE files are not followed (convert them one by one).

Formats: *NODE and *ELEMENT_SOLID in fixed columns (I8/E16 nodes, I8 elements, the one-line
legacy or the two-line layout) or comma-separated. Units and everything else: unchanged.

usage: /usr/bin/python3 input/hex_to_tet.py deck.k tet_deck.k [--elform 43|13|10]
"""
import argparse
import sys

TET_PATTERN = 12                # tets per hexahedron
# faces of an 8-node hexahedron (LS-DYNA node order), each counter-clockwise seen from outside
HEX_FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def fields(line, widths):
    """The fields of a card: comma-separated, or fixed columns of the given widths."""
    if ',' in line:
        return [f.strip() for f in line.split(',')]
    out, start = [], 0
    for w in widths:
        out.append(line[start:start + w].strip())
        start += w
    return out


def keyword_blocks(lines):
    """(keyword line index, keyword name, data line indices) for every keyword."""
    blocks, current = [], None
    for i, line in enumerate(lines):
        if line.startswith('*'):
            current = (i, line.strip().upper(), [])
            blocks.append(current)
        elif current is not None and not line.startswith('$'):
            current[2].append(i)
    return blocks


def read_nodes(lines, blocks):
    """{node id: (x, y, z)} of every *NODE block."""
    nodes = {}
    for _, name, data in blocks:
        if name.split()[0] != '*NODE':
            continue
        for i in data:
            f = fields(lines[i], [8, 16, 16, 16, 8, 8])
            if not f[0]:
                continue
            nodes[int(f[0])] = tuple(float(v or 0.0) for v in f[1:4])
    return nodes


def read_solids(lines, data):
    """The elements of one *ELEMENT_SOLID block: [(first line, last line, eid, pid, nodes)]."""
    out, k = [], 0
    while k < len(data):
        i = data[k]
        f = [v for v in fields(lines[i], [8] * 10) if v != '']
        if len(f) > 2:                               # one line: EID PID N1 ... N8
            out.append((i, i, int(f[0]), int(f[1]), [int(v) for v in f[2:10]]))
            k += 1
        else:                                        # two lines: EID PID / N1 ... N10
            g = [int(v) for v in fields(lines[data[k + 1]], [8] * 10) if v != '']
            out.append((i, data[k + 1], int(f[0]), int(f[1]), g[:8]))
            k += 2
    return out


def split_hex(nodes_of_hex, centre):
    """The 12 tets (node ids) of a hexahedron with its centroid node."""
    tets = []
    for face in HEX_FACES:
        q = [nodes_of_hex[v] for v in face]
        low = q.index(min(q))                        # diagonal through the lowest node id
        a, b, c, d = q[low:] + q[:low]
        # outward face a-b-c-d: triangles (a, b, c) and (a, c, d); seen from the centroid (inside)
        # they turn the other way, so the tets (a, c, b, centre) are positively oriented
        tets.append([a, c, b, centre])
        tets.append([a, d, c, centre])
    return tets


def convert(lines, elform):
    """The converted deck's lines and a summary."""
    blocks = keyword_blocks(lines)
    nodes = read_nodes(lines, blocks)
    next_node = max(nodes) + 1 if nodes else 1
    elements = []
    for _, name, data in blocks:
        if name.split()[0] == '*ELEMENT_SOLID':
            elements += read_solids(lines, data)
    next_element = max((e[2] for e in elements), default=0) + 1
    replace, new_nodes, split_parts = {}, [], set()
    for first, last, eid, pid, conn in elements:
        if len(conn) < 8 or len(set(conn[:8])) != 8:
            continue                                 # a tet, wedge or other degenerate solid
        x = [nodes[n] for n in conn[:8]]
        centre = next_node
        next_node += 1
        new_nodes.append((centre, [sum(p[k] for p in x) / 8.0 for k in range(3)]))
        tets = split_hex(conn[:8], centre)
        ids = [eid] + list(range(next_element, next_element + len(tets) - 1))
        next_element += len(tets) - 1
        replace[first] = ['%8d%8d' % (i, pid) + ''.join('%8d' % n for n in t + [t[3]] * 4)
                          for i, t in zip(ids, tets)]
        if last != first:
            replace[last] = []
        split_parts.add(pid)
    sections = set()
    for _, name, data in blocks:
        if name.split()[0] == '*PART':
            for k in range(1, len(data), 2):
                f = fields(lines[data[k]], [10] * 8)
                if f[0] and int(f[0]) in split_parts:
                    sections.add(int(f[1]))
    out = []
    node_block_done = False
    for i, line in enumerate(lines):
        if i in replace:
            out += replace[i]
            continue
        out.append(line)
        if line.strip().upper().startswith('*NODE') and not node_block_done and new_nodes:
            out.append('$ centroids of the hexahedra split by input/hex_to_tet.py')
            out += ['%8d%16.9g%16.9g%16.9g' % (n, *p) for n, p in new_nodes]
            node_block_done = True
    # the sections of the split parts: ELFORM
    blocks = keyword_blocks(out)
    for _, name, data in blocks:
        if not name.startswith('*SECTION_SOLID'):
            continue
        title = 1 if '_TITLE' in name else 0
        for i in data[title:]:
            f = fields(out[i], [10] * 8)
            if f[0] and int(f[0]) in sections:
                if ',' in out[i]:
                    parts = out[i].split(',')
                    parts[1] = str(elform)
                    out[i] = ','.join(parts)
                else:
                    out[i] = out[i][:10] + '%10d' % elform + out[i][20:]
    summary = '%d hexahedra split into %d tetrahedra (%d new nodes); parts %s, sections %s ' \
              'now ELFORM %d' % (len(new_nodes), TET_PATTERN * len(new_nodes), len(new_nodes),
                                 sorted(split_parts), sorted(sections), elform)
    return out, summary


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('deck')
    ap.add_argument('output')
    ap.add_argument('--elform', type=int, default=43, choices=(43, 13, 10))
    a = ap.parse_args(argv)
    with open(a.deck, encoding='latin-1') as f:
        lines = f.read().split('\n')
    out, summary = convert(lines, a.elform)
    with open(a.output, 'w', encoding='latin-1') as f:
        f.write('\n'.join(out))
    print(summary)


if __name__ == '__main__':
    main(sys.argv[1:])
