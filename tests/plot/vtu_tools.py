"""Rewrites a VTU file read by scripts/vpcontact_plot.py, for the plot tests:
raw or zlib-compressed appended data (the layout of VTK's
vtkZLibDataCompressor: per array a header [n_blocks, block size, size of the
last block, compressed size of each block] then the zlib blocks), fields
renamed or added. It lets the tests exercise the reader's compressed path and
the field fallbacks before (and independently of) the C++ writer.

Usage as a script:
  vtu_tools.py compress IN.vtu OUT.vtu [BLOCK_BYTES]
  vtu_tools.py damage-to-beta IN.vtu OUT.vtu     (point field damage -> beta; beta-to-damage: back)
  vtu_tools.py add-pressure IN.vtu OUT.vtu       (contact_pressure = |contact_force| / tributary area)
"""

import os
import sys
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import vpcontact_plot as vp  # noqa: E402

_TYPES = {"f8": "Float64", "f4": "Float32", "i8": "Int64", "i4": "Int32", "u1": "UInt8", "u8": "UInt64"}


def _vtk_type(a):
    return _TYPES[a.dtype.str.lstrip("<|")]


def _block(a, compress, block_bytes, header):
    import numpy as np

    data = np.ascontiguousarray(a).astype(a.dtype.newbyteorder("<"), copy=False).tobytes()
    if not compress:
        return np.array([len(data)], header).tobytes() + data
    chunks = [data[i:i + block_bytes] for i in range(0, len(data), block_bytes)] or []
    packed = [zlib.compress(c) for c in chunks]
    last = len(chunks[-1]) if chunks and len(chunks[-1]) != block_bytes else 0
    head = [len(chunks), block_bytes, last] + [len(p) for p in packed]
    return np.array(head, header).tobytes() + b"".join(packed)


def write_vtu(path, vtu, compress=False, block_bytes=32768, header="<u8"):
    """Writes vtu (a vp.Vtu) as an UnstructuredGrid with appended data;
    header: the type of the block headers ('<u8' or '<u4')."""
    import numpy as np

    blobs = []
    offset = [0]

    def array(name, a, extra=""):
        a = np.asarray(a)
        nc = a.shape[1] if a.ndim == 2 else 1
        b = _block(a, compress, block_bytes, header)
        tag = '<DataArray type="%s"%s NumberOfComponents="%d" format="appended" offset="%d"%s/>\n' % (
            _vtk_type(a), ' Name="%s"' % name if name else "", nc, offset[0], extra)
        blobs.append(b)
        offset[0] += len(b)
        return tag

    n, m = len(vtu.points), len(vtu.cells)
    xml = ['<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
           'header_type="%s"%s>\n' % ({"<u8": "UInt64", "<u4": "UInt32"}[header],
                                        ' compressor="vtkZLibDataCompressor"' if compress else ""),
           '<UnstructuredGrid>\n<Piece NumberOfPoints="%d" NumberOfCells="%d">\n<PointData>\n' % (n, m)]
    xml += [array(k, v) for k, v in vtu.point_data.items()]
    xml.append("</PointData>\n<CellData>\n")
    xml += [array(k, v) for k, v in vtu.cell_data.items()]
    xml.append("</CellData>\n<Points>\n")
    xml.append(array(None, vtu.points))
    xml.append("</Points>\n<Cells>\n")
    k = vtu.cells.shape[1]
    xml.append(array("connectivity", vtu.cells.astype("<i8").ravel()))
    xml.append(array("offsets", (np.arange(1, m + 1) * k).astype("<i8")))
    xml.append(array("types", np.full(m, vtu.cell_type, "u1")))
    xml.append('</Cells>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding="raw">\n_')
    with open(path, "wb") as f:
        f.write("".join(xml).encode())
        for b in blobs:
            f.write(b)
        f.write(b"\n</AppendedData>\n</VTKFile>\n")


def rename(vtu, old, new):
    vtu.point_data = {(new if k == old else k): v for k, v in vtu.point_data.items()}


def add_pressure(vtu):
    """contact_pressure = |contact_force| / (a third of the area of the lower
    boundary faces around the node): the writer's definition on a flat Γ3 away
    from its edges, good enough to exercise the figure."""
    import numpy as np

    f = np.linalg.norm(vtu.point("contact_force"), axis=1)
    faces, _ = vp.contact_boundary(vtu.points, vtu.cells, np.ones(len(vtu.points)))
    p = vtu.points
    area = 0.5 * np.linalg.norm(np.cross(p[faces[:, 1]] - p[faces[:, 0]], p[faces[:, 2]] - p[faces[:, 0]]), axis=1)
    trib = np.zeros(len(p))
    for c in range(3):
        np.add.at(trib, faces[:, c], area / 3.0)
    vtu.point_data["contact_pressure"] = np.where(trib > 0, f / np.maximum(trib, 1e-300), 0.0)


def main(argv):
    cmd, src, dst = argv[1], argv[2], argv[3]
    vtu = vp.read_vtu(src)
    if cmd == "compress":
        write_vtu(dst, vtu, compress=True, block_bytes=int(argv[4]) if len(argv) > 4 else 32768)
    elif cmd == "damage-to-beta":
        rename(vtu, "damage", "beta")
        write_vtu(dst, vtu)
    elif cmd == "beta-to-damage":
        rename(vtu, "beta", "damage")
        write_vtu(dst, vtu)
    elif cmd == "add-pressure":
        add_pressure(vtu)
        write_vtu(dst, vtu)
    else:
        raise SystemExit("unknown command " + cmd)


if __name__ == "__main__":
    main(sys.argv)
