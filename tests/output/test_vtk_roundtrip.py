"""Round trip of the VTK XML writer (src/io/vtk_output.f90) through VTK's own readers.

The unit test tests/unit/test_vtk_output.f90 (run before the script tests, on 1 and 3 ranks)
writes tests/out/vtk_unit/np<ranks>/: the VTK files (mesh.pvd, .vtu/.pvtu of steps 0 and 10)
and truth_rank<r>.txt, the numbers each rank handed to the writer. This script opens mesh.pvd,
reads every state with vtkXMLUnstructuredGridReader (1 rank) or vtkXMLPUnstructuredGridReader
(3 ranks) and compares with the truth: point and cell counts, coordinates, cell types,
connectivity, offsets, ids, fields (integers exact, Float64 within 1e-15 relative), and the
times of the .pvd. It also runs the unit test binary with --bad-dir and expects a clean error.
Missing or stale output is a failure. Prints one PASS/FAIL line per check; exit code 1 on failure.

Environment: MEFEM_ROOT (project root; default: two levels above this file),
MEFEM_VTK_TEST_BIN (unit test binary; default build/debug/tests/test_vtk_output).
"""
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import (VTK_DOUBLE, VTK_INT, vtkLogger, vtkOutputWindow,
                                      vtkStringOutputWindow)
from vtkmodules.vtkIOXML import vtkXMLPUnstructuredGridReader, vtkXMLUnstructuredGridReader

ROOT = os.environ.get("MEFEM_ROOT") or os.path.dirname(
    os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "tests", "out", "vtk_unit")
BINARY = os.environ.get("MEFEM_VTK_TEST_BIN") or os.path.join(
    ROOT, "build", "debug", "tests", "test_vtk_output")
RANK_COUNTS = (1, 3)      # the "! ranks:" line of the unit test
RTOL = 1.0e-15            # relative tolerance on Float64 values

failures = 0


def report(ok, what, detail=""):
    """Print one PASS/FAIL line and count failures."""
    global failures
    if ok:
        print(f"PASS: {what}")
    else:
        failures += 1
        print(f"FAIL: {what}: {detail}")
    return ok


def read_truth(path):
    """Parse a truth file: {'arrays': {name: ndarray}, 'states': [(step, time, file)], ...}."""
    truth = {"arrays": {}, "states": []}
    with open(path) as f:
        lines = f.read().splitlines()
    i = 0
    while i < len(lines):
        words = lines[i].split()
        i += 1
        if not words:
            continue
        if words[0] in ("nranks", "rank"):
            truth[words[0]] = int(words[1])
        elif words[0] == "state":
            truth["states"].append((int(words[1]), float(words[2]), words[3]))
        elif words[0] == "array":
            name, kind, ncomp, count = words[1], words[2], int(words[3]), int(words[4])
            rows = [line.split() for line in lines[i:i + count]]
            i += count
            if kind == "i":
                values = np.array([int(v) for row in rows for v in row], dtype=np.int64)
            else:
                values = np.array([float(v) for row in rows for v in row], dtype=np.float64)
            truth["arrays"][name] = values.reshape(count, ncomp) if ncomp > 1 else values
        else:
            raise ValueError(f"{path}: unexpected line {lines[i - 1]!r}")
    return truth


def close(got, want):
    """Float64 comparison: |got - want| <= RTOL |want| element-wise (zeros exact), NaN fails."""
    got, want = np.asarray(got, dtype=np.float64), np.asarray(want, dtype=np.float64)
    if got.shape != want.shape:
        return False, f"shape {got.shape} != {want.shape}"
    excess = np.abs(got - want) - RTOL * np.abs(want)
    if np.any(np.isnan(got)) or np.any(excess > 0):
        k = int(np.argmax(np.where(np.isnan(excess), np.inf, excess)))
        return False, f"entry {k}: got {got.flat[k]!r} want {want.flat[k]!r}"
    return True, ""


def equal(got, want):
    """Exact comparison of integer arrays."""
    got, want = np.asarray(got), np.asarray(want)
    if got.shape != want.shape:
        return False, f"shape {got.shape} != {want.shape}"
    bad = np.nonzero(got != want)[0] if got.ndim == 1 else np.nonzero(np.any(got != want, 1))[0]
    if bad.size:
        return False, f"entry {bad[0]}: got {got[bad[0]]} want {want[bad[0]]}"
    return True, ""


def check_raw_header(path, label):
    """The piece uses raw appended binary with UInt64 headers and the required types."""
    with open(path, "rb") as f:
        head = f.read(8192).split(b"<AppendedData", 1)[0].decode("ascii", "replace")
    want = [r'byte_order="LittleEndian"', r'header_type="UInt64"',
            r'type="Float64" NumberOfComponents="3" format="appended"',
            r'type="Int64" Name="connectivity" format="appended"',
            r'type="Int64" Name="offsets" format="appended"',
            r'type="UInt8" Name="types" format="appended"',
            r'type="Int32" Name="node_id"', r'type="Int32" Name="element_id"',
            r'type="Int32" Name="part_id"']
    with open(path, "rb") as f:
        raw = b'<AppendedData encoding="raw">' in f.read()
    missing = [w for w in want if not re.search(re.escape(w), head)]
    report(raw and not missing, f"{label}: raw appended UInt64-header layout and types",
           f"missing {missing}" if missing else "no raw AppendedData")


def read_grid(path, log):
    """Read a .vtu or .pvtu; returns (grid or None, error text)."""
    reader = (vtkXMLPUnstructuredGridReader() if path.endswith(".pvtu")
              else vtkXMLUnstructuredGridReader())
    before = log.GetOutput()
    reader.SetFileName(path)
    reader.Update()
    messages = log.GetOutput()[len(before):]
    if "ERR" in messages or "Error" in messages:
        return None, messages.strip().replace("\n", " | ")[:400]
    return reader.GetOutput(), ""


def check_state(grid, truths, step, label):
    """Compare one state read by VTK with the concatenated truth of all ranks."""
    arrays = [t["arrays"] for t in truths]
    nnode = [len(a["node_id"]) for a in arrays]
    ncell = [len(a["element_id"]) for a in arrays]
    report(grid.GetNumberOfPoints() == sum(nnode), f"{label}: number of points",
           f"{grid.GetNumberOfPoints()} != {sum(nnode)}")
    report(grid.GetNumberOfCells() == sum(ncell), f"{label}: number of cells",
           f"{grid.GetNumberOfCells()} != {sum(ncell)}")
    if grid.GetNumberOfPoints() != sum(nnode) or grid.GetNumberOfCells() != sum(ncell):
        return
    ok, detail = close(vtk_to_numpy(grid.GetPoints().GetData()),
                       np.concatenate([a["points"] for a in arrays]))
    report(ok, f"{label}: coordinates", detail)
    ok, detail = equal(vtk_to_numpy(grid.GetCellTypesArray()),
                       np.concatenate([a["types"] for a in arrays]))
    report(ok, f"{label}: cell types", detail)

    # pieces are appended in rank order: shift each piece's 0-based node numbers
    node_shift = np.cumsum([0] + nnode[:-1])
    entry_shift = np.cumsum([0] + [len(a["connectivity"]) for a in arrays[:-1]])
    want_conn = np.concatenate([a["connectivity"] + s for a, s in zip(arrays, node_shift)])
    want_offsets = np.concatenate([[0]] + [a["offsets"] + s for a, s in zip(arrays, entry_shift)])
    cells = grid.GetCells()
    ok, detail = equal(vtk_to_numpy(cells.GetConnectivityArray()), want_conn)
    report(ok, f"{label}: connectivity", detail)
    ok, detail = equal(vtk_to_numpy(cells.GetOffsetsArray()), want_offsets)
    report(ok, f"{label}: offsets", detail)

    # the node ids again as the points' global ids (Int64): VTK and ParaView join the copies
    # of a node on the pieces' cuts by them
    global_ids = grid.GetPointData().GetGlobalIds()
    ok = global_ids is not None and global_ids.GetName() == "GlobalNodeIds"
    detail = "no GlobalIds array" if global_ids is None else global_ids.GetName()
    if ok:
        ok, detail = equal(vtk_to_numpy(global_ids), np.concatenate([a["node_id"] for a in arrays]))
        if global_ids.GetDataTypeSize() != 8:
            ok, detail = False, f"type {global_ids.GetDataTypeAsString()}, want a 64-bit id"
    report(ok, f"{label}: point data GlobalIds GlobalNodeIds = the node ids (64-bit)", detail)
    # the cells' global positions as the cells' global ids (Int64): every cell of the mesh once
    cell_ids = grid.GetCellData().GetGlobalIds()
    ok = cell_ids is not None and cell_ids.GetName() == "GlobalCellIds"
    detail = "no GlobalIds array" if cell_ids is None else cell_ids.GetName()
    if ok:
        ok, detail = equal(np.sort(vtk_to_numpy(cell_ids)), np.arange(sum(ncell)))
        if cell_ids.GetDataTypeSize() != 8:
            ok, detail = False, f"type {cell_ids.GetDataTypeAsString()}, want a 64-bit id"
    report(ok, f"{label}: cell data GlobalIds GlobalCellIds = the cells' global positions "
           "0 .. ncell-1, each once (64-bit)", detail)
    # the state's time as the grid's field data TimeValue
    times = [time for s, time, _ in truths[0]["states"] if s == step]
    value = grid.GetFieldData().GetArray("TimeValue")
    report(value is not None and len(times) == 1 and value.GetValue(0) == times[0],
           f"{label}: field data TimeValue = the state's time",
           f"{None if value is None else value.GetValue(0)} vs {times}")
    point_names = ["node_id", "GlobalNodeIds"] + sorted(n.split(":")[1] for n in arrays[0]
                                      if n.startswith("point:") and n.endswith(f":{step}"))
    cell_names = ["element_id", "part_id", "GlobalCellIds"] + sorted(
        n.split(":")[1] for n in arrays[0] if n.startswith("cell:") and n.endswith(f":{step}"))
    for kind, data, names in (("point", grid.GetPointData(), point_names),
                              ("cell", grid.GetCellData(), cell_names)):
        got_names = sorted(data.GetArrayName(k) for k in range(data.GetNumberOfArrays()))
        report(got_names == sorted(names), f"{label}: {kind} data arrays are {names}",
               f"got {got_names}")
        for name in names:
            array = data.GetArray(name)
            if array is None:
                continue
            if name in ("GlobalNodeIds", "GlobalCellIds"):
                continue                                  # (checked above)
            if name in ("node_id", "element_id", "part_id"):
                ok, detail = equal(vtk_to_numpy(array),
                                   np.concatenate([a[name] for a in arrays]))
                if array.GetDataType() != VTK_INT:
                    ok, detail = False, f"type {array.GetDataTypeAsString()}, want int (Int32)"
            else:
                want = np.concatenate([a[f"{kind}:{name}:{step}"] for a in arrays])
                ok, detail = close(vtk_to_numpy(array), want)
                if array.GetDataType() != VTK_DOUBLE:
                    ok, detail = False, f"type {array.GetDataTypeAsString()}, want double"
            report(ok, f"{label}: {kind} array {name}", detail)


def check_rank_count(nranks, log):
    """All checks of the output written on nranks ranks."""
    tag = f"vtk np={nranks}"
    directory = os.path.join(OUT, f"np{nranks}")
    truth_paths = [os.path.join(directory, f"truth_rank{r}.txt") for r in range(nranks)]
    missing = [p for p in truth_paths + [os.path.join(directory, "mesh.pvd")]
               if not os.path.isfile(p)]
    if not report(not missing, f"{tag}: unit test output present",
                  f"missing {missing} (run test_vtk_output on {nranks} rank(s) first)"):
        return
    if os.path.isfile(BINARY):
        stale = [p for p in truth_paths if os.path.getmtime(p) < os.path.getmtime(BINARY)]
        if not report(not stale, f"{tag}: output newer than the unit test binary",
                      f"stale {stale}"):
            return
    truths = [read_truth(p) for p in truth_paths]
    report(all(t["nranks"] == nranks and t["rank"] == r for r, t in enumerate(truths)),
           f"{tag}: truth files belong to this run", "nranks/rank mismatch")

    # the collection: both states, right files and times, in order
    collection = ElementTree.parse(os.path.join(directory, "mesh.pvd")).getroot()
    datasets = collection.findall("./Collection/DataSet")
    got = [(d.get("file"), float(d.get("timestep"))) for d in datasets]
    want = [(f, t) for _, t, f in truths[0]["states"]]
    report(collection.get("type") == "Collection" and got == want,
           f"{tag}: mesh.pvd lists both steps with their times", f"got {got}, want {want}")

    for (step, _, file_name) in truths[0]["states"]:
        label = f"{tag} step {step}"
        report("/" not in file_name and not os.path.isabs(file_name),
               f"{label}: .pvd refers to a relative file", file_name)
        path = os.path.join(directory, file_name)
        if not report(os.path.isfile(path), f"{label}: {file_name} exists", path):
            continue
        pieces = [path]
        if nranks > 1:
            report(file_name.endswith(".pvtu"), f"{label}: several ranks give a .pvtu", file_name)
            index = ElementTree.parse(path).getroot()
            sources = [p.get("Source") for p in index.findall("./PUnstructuredGrid/Piece")]
            want_sources = [file_name[:-5] + f"_{r:04d}.vtu" for r in range(nranks)]
            report(sources == want_sources, f"{label}: .pvtu lists the pieces relatively",
                   f"got {sources}, want {want_sources}")
            pieces = [os.path.join(directory, s) for s in want_sources]
        else:
            report(file_name.endswith(".vtu") and not os.path.exists(path[:-4] + ".pvtu"),
                   f"{label}: one rank gives a single .vtu and no .pvtu", file_name)
        for piece in pieces:
            if os.path.isfile(piece):
                check_raw_header(piece, f"{label} {os.path.basename(piece)}")
        grid, error = read_grid(path, log)
        if report(grid is not None, f"{label}: VTK reads {file_name} without error", error):
            check_state(grid, truths, step, label)


def check_bad_directory():
    """Writing into a missing directory stops with a message naming the file, creates nothing."""
    tag = "vtk error path"
    if not report(os.path.isfile(BINARY), f"{tag}: unit test binary present", BINARY):
        return
    missing_dir = os.path.join(OUT, "missing_directory")
    env = dict(os.environ, MEFEM_ROOT=ROOT, OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    try:
        run = subprocess.run([BINARY, "--bad-dir"], cwd=os.path.join(ROOT, "tests", "unit"),
                             env=env, capture_output=True, text=True, timeout=120)
    except subprocess.TimeoutExpired:
        report(False, f"{tag}: writer stops", "timed out after 120 s")
        return
    text = run.stdout + run.stderr
    report(run.returncode != 0, f"{tag}: non-zero exit", f"exit code {run.returncode}")
    report(re.search(r"mefem: error: vtk_write_state: cannot open \S*missing_directory/"
                     r"mesh_000001\.vtu for writing: \S", text) is not None,
           f"{tag}: message names the file and the reason", text.strip()[:400])
    report(not os.path.exists(missing_dir), f"{tag}: the directory is not created", missing_dir)


def main():
    # VTK's messages go to a string that read_grid inspects, not to the terminal
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    log = vtkStringOutputWindow()
    vtkOutputWindow.SetInstance(log)
    for nranks in RANK_COUNTS:
        try:
            check_rank_count(nranks, log)
        except Exception as error:  # unreadable truth or XML: a failure, not a crash
            report(False, f"vtk np={nranks}: output readable", f"{type(error).__name__}: {error}")
    check_bad_directory()
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
