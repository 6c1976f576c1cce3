#!/usr/bin/env python3
"""Reads VTU files with VTK's own reader (what ParaView uses) and checks that the
zlib-compressed and the raw files of the same run hold the same arrays, exactly.

  read_with_vtk.py ZLIB_DIR NONE_DIR   compares every solution_*.vtu (or .pvtu) of
                                       the two output directories
Exits 0 when all agree, 1 (with the difference) otherwise.
"""
import glob
import os
import sys

import vtk


def values(array):
    """The values of a vtkDataArray, as a flat list (no numpy needed)."""
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


def read(path):
    reader = vtk.vtkXMLPUnstructuredGridReader() if path.endswith(".pvtu") else vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0:
        raise SystemExit("%s: VTK could not read it (error code %d)" % (path, reader.GetErrorCode()))
    grid = reader.GetOutput()
    arrays = {"Points": values(grid.GetPoints().GetData()),
              "connectivity": values(grid.GetCells().GetConnectivityArray()),
              "types": values(grid.GetCellTypesArray())}
    for kind, data in (("point", grid.GetPointData()), ("cell", grid.GetCellData())):
        for i in range(data.GetNumberOfArrays()):
            arrays[kind + ":" + data.GetArrayName(i)] = values(data.GetArray(i))
    return arrays


def main(zlib_dir, none_dir):
    files = sorted(os.path.basename(f) for f in glob.glob(os.path.join(zlib_dir, "solution_*.*vtu"))
                   if "_p" not in os.path.basename(f))
    if not files:
        raise SystemExit("no solution_*.vtu in %s" % zlib_dir)
    for name in files:
        with open(os.path.join(zlib_dir, name), "rb") as f:
            head = f.read(400)
        if name.endswith(".vtu") and b'compressor="vtkZLibDataCompressor"' not in head:
            raise SystemExit("%s/%s is not compressed" % (zlib_dir, name))
        a, b = read(os.path.join(zlib_dir, name)), read(os.path.join(none_dir, name))
        if sorted(a) != sorted(b):
            raise SystemExit("%s: arrays differ: %s vs %s" % (name, sorted(a), sorted(b)))
        for key in a:
            if not a[key] or a[key] != b[key]:
                raise SystemExit("%s: array %s differs" % (name, key))
        print("%s: %d arrays equal (%s; %d points)" % (name, len(a), ", ".join(sorted(a)), len(a["Points"]) // 3))
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:3]))
