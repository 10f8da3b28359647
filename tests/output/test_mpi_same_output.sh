#!/usr/bin/env bash
# The same deck run on 1, 2 and 3 MPI ranks must write the same data: the HDF5 files must hold
# identical datasets (rows in global id order), and the VTK output of every run must read
# back (VTK's own reader) with all cells and node ids present.
set -u
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
out=tests/out/mpi_same_output
rm -rf "$out"; mkdir -p "$out"
deck=$out/block.k
/usr/bin/python3 tests/bench/generate_block_deck.py 6 5 4 "$deck.mesh" --tets 5 > /dev/null || {
  echo "FAIL: mpi_same_output: deck generation failed"; exit 1; }
# the mesh deck plus a node set, so that set output is compared too
{ sed '/^\*END/d' "$deck.mesh"
  printf '*SET_NODE_LIST\n         7\n         1         2         3         4        10        20\n*END\n'
} > "$deck"
for np in 1 2 3; do
  if ! mpirun --oversubscribe -np $np bin/mefem -o "$out/np$np" "$deck" > "$out/np$np.log" 2>&1; then
    echo "FAIL: mpi_same_output: run on $np rank(s) failed:"; sed 's/^/    /' "$out/np$np.log" | tail -5
    exit 1
  fi
done
/usr/bin/python3 - "$out" <<'PY'
import sys, os, glob
import numpy as np, h5py
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLPUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy
out = sys.argv[1]
ok = True
def report(cond, what, detail=''):
    global ok
    print(('PASS: mpi_same_output: ' if cond else 'FAIL: mpi_same_output: ') + what +
          ('' if cond else ': ' + detail))
    ok = ok and cond
def datasets(path):
    found = {}
    with h5py.File(path, 'r') as f:
        f.visititems(lambda name, obj: found.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None)
    return found
ref = datasets(os.path.join(out, 'np1', 'block.h5'))
report('/mesh/coordinates' in ref or 'mesh/coordinates' in ref, 'serial HDF5 file has mesh/coordinates')
for np_ in (2, 3):
    other = datasets(os.path.join(out, 'np%d' % np_, 'block.h5'))
    report(sorted(other) == sorted(ref), 'np=%d HDF5 has the same datasets' % np_,
           '%s vs %s' % (sorted(other), sorted(ref)))
    for name in ref:
        if name not in other:
            continue
        same = ref[name].shape == other[name].shape and np.array_equal(ref[name], other[name])
        report(same, 'np=%d dataset %s identical to serial' % (np_, name))
nnode = ref['mesh/node_ids'].shape[0]
ncell = ref['mesh/cell_ids'].shape[0]
for np_ in (1, 2, 3):
    d = os.path.join(out, 'np%d' % np_)
    files = glob.glob(os.path.join(d, 'block_000000.pvtu' if np_ > 1 else 'block_000000.vtu'))
    report(len(files) == 1, 'np=%d VTK state file present' % np_)
    if not files:
        continue
    r = vtkXMLPUnstructuredGridReader() if np_ > 1 else vtkXMLUnstructuredGridReader()
    r.SetFileName(files[0]); r.Update()
    g = r.GetOutput()
    report(g.GetNumberOfCells() == ncell, 'np=%d VTK cells = %d' % (np_, ncell), str(g.GetNumberOfCells()))
    ids = vtk_to_numpy(g.GetPointData().GetArray('node_id'))
    report(len(np.unique(ids)) == nnode, 'np=%d VTK holds every node id' % np_)
    s7 = g.GetPointData().GetArray('node_set_7')
    report(s7 is not None and int(vtk_to_numpy(s7)[np.unique(ids, return_index=True)[1]].sum()) == 6,
           'np=%d node set 7 written with its 6 members' % np_)
sys.exit(0 if ok else 1)
PY
