#!/usr/bin/env python3
"""Writes the hostile mesh files of this folder and expected.txt: for each file, the substring its
import error must hold (what is wrong and where). Run it here to remake them; the test reads them."""
import struct

files = []  # (name, bytes, expected message part)

def add(name, data, expect):
    files.append((name, data if isinstance(data, bytes) else data.encode(), expect))

TET_V = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
TET_F = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"

# --- OFF ---
add("huge_count.off", "OFF\n3 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "line 2: the header declares 3 vertices and 2000000000 faces")
add("huge_vertices.off", "OFF\n1000000000 1 0\n0 0 0\n", "declares 1000000000 vertices")
add("negative_count.off", "OFF\n-4 4 0\n", "line 2: negative count -4")
add("count_overflow.off", "OFF\n99999999999999999999 1 0\n", "is out of range")
PAD = "# padding, so that the counts fit the file's size\n" * 2
add("few_vertices.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n" + TET_F + PAD, "the file ends after 3 of the header's 4 faces")
add("truncated.off", "OFF\n4 4 0\n" + TET_V + "3 0 2 1\n3 0 1 3\n" + PAD, "ends after 2 of the header's 4 faces")
add("counts_exceed_size.off", "OFF\n4 4 0\n" + TET_V + "3 0 2 1\n", "the header declares 4 vertices and 4 faces, but the 32 bytes after it can hold at most 17 numbers")
add("index_range.off", "OFF\n4 4 0\n" + TET_V + "3 0 2 1\n3 0 1 3\n3 0 3 7\n3 1 2 3\n", "line 9: face 2: index 7 is out of range (4 vertices")
add("negative_index.off", "OFF\n4 4 0\n" + TET_V + "3 0 2 -1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", "face 0: index -1 is out of range")
add("nan.off", "OFF\n4 4 0\n0 0 0\nnan 0 0\n0 1 0\n0 0 1\n" + TET_F, "line 4: vertex 1 coordinate: non-finite number 'nan'")
add("inf.off", "OFF\n4 4 0\n0 0 0\n1e999 0 0\n0 1 0\n0 0 1\n" + TET_F, "line 4: vertex 1 coordinate: '1e999' is out of range")
add("word.off", "OFF\n4 4 0\n0 0 0\n1 zero 0\n0 1 0\n0 0 1\n" + TET_F, "line 4: vertex 1 coordinate: 'zero' is not a number")
add("two_corners.off", "OFF\n4 1 0\n" + TET_V + "2 0 1\n", "line 7: face 0 has 2 corners, needs at least 3")
add("short_face.off", "OFF\n4 1 0\n" + TET_V + "5 0 1 2\n", "line 7: face 0 declares 5 corners but the line holds 3 indices")
add("extra_faces.off", "OFF\n4 4 0\n" + TET_V + TET_F + "3 0 1 2\n", "line 11: more data after the header's 4 faces")
add("not_off.off", "this is not an OFF file\n", "not an OFF file")
add("four_d.off", "4OFF\n1 1 0\n", "higher-dimensional OFF")
add("binary.off", "OFF BINARY\n" + "\0" * 12, "binary OFF is not supported")
add("comments_only.off", "# nothing\n\n# here\n", "holds only comments")
add("no_faces.off", "OFF\n4 0 0\n" + TET_V, "holds no triangles")

# --- PLY ---
PLY_HEAD = "ply\nformat {fmt} 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\nproperty float z\nelement face {nf}\nproperty list uchar int vertex_indices\nend_header\n"
def ply(nv, nf, body, fmt="ascii"):
    return PLY_HEAD.format(fmt=fmt, nv=nv, nf=nf) + body
add("huge_count.ply", ply(1000000000, 1, "0 0 0\n"), "header line 3: element 'vertex' declares 1000000000 items")
add("truncated_ascii.ply", ply(4, 4, TET_V + "3 0 2 1\n"), "the file ends at face 1 property 'vertex_indices'")
add("index_range.ply", ply(4, 4, TET_V + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 9\n"), "face 3 corner 2: index 9 is out of range (4 vertices")
add("nan.ply", ply(4, 4, "0 0 0\n1 0 0\n0 nan 0\n0 0 1\n" + TET_F), "line 12: vertex 2 property 'y': non-finite number 'nan'")
add("no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 3\n", "no 'end_header' line")
add("bad_type.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty quad x\nend_header\n", "header line 4: unknown type 'quad'")
add("bad_format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n", "unknown format 'binary_middle_endian'")
add("no_xyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float a\nend_header\n1\n", "the 'vertex' element has no x, y and z")
add("float_list_count.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n3 0 1 2\n", "a list count must be an integer type")
add("not_ply.ply", "solid x\n", "not a PLY file")
add("extra.ply", ply(4, 4, TET_V + TET_F + "7\n"), "more data after the last element")
# Binary: the face list claims 200 corners in a file that holds 12 bytes after it.
v = b"".join(struct.pack("<3f", *p) for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)])
add("list_overrun.ply", ply(4, 1, "", "binary_little_endian").encode() + v + bytes([200]) + struct.pack("<3i", 0, 1, 2),
    "face 0 declares 200 corners, more than the rest of the file holds")
add("counts_exceed_size.ply", ply(4, 4, "", "binary_little_endian").encode() + v[:20], "element 'vertex' declares 4 items of at least 12 bytes, but the 20 bytes")
add("truncated_binary.ply", ply(4, 4, "", "binary_little_endian").encode() + v + bytes([3, 3, 3, 3]), "byte 218: face 0 declares 3 corners, more than the rest of the file holds")
add("binary_nan.ply", ply(1, 1, "", "binary_little_endian").encode() + struct.pack("<3f", 0, float("inf"), 0) + bytes([3]) + struct.pack("<3i", 0, 0, 0),
    "vertex 0 property 'y' is not finite")

# --- STL ---
def tri(a, b, c):
    return struct.pack("<3f", 0, 0, 0) + struct.pack("<9f", *a, *b, *c) + b"\0\0"
T = tri((0, 0, 0), (1, 0, 0), (0, 1, 0))
add("truncated.stl", b"x" * 80 + struct.pack("<I", 1000) + T * 2, "binary STL declares 1000 triangles (50084 bytes) but the file has 184 bytes: truncated")
add("huge_count.stl", b"x" * 80 + struct.pack("<I", 0xFFFFFFFF), "declares 4294967295 triangles")
add("trailing.stl", b"x" * 80 + struct.pack("<I", 1) + T + b"junk", "4 bytes after the last triangle")
add("nan.stl", b"x" * 80 + struct.pack("<I", 2) + T + tri((0, 0, 0), (float("nan"), 0, 0), (0, 1, 0)), "triangle 2 (byte 158): corner 2 has a non-finite coordinate")
add("short.stl", b"tiny", "too short for a binary one (4 bytes")
add("zero.stl", b"x" * 80 + struct.pack("<I", 0), "holds no triangles")
add("ascii_truncated.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n", "the file ends inside a facet (truncated)")
add("ascii_word.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 oops 0\n", "line 5: vertex: 'oops' is not a number")
add("ascii_quad.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n", "line 7: a facet with more than 3 vertices")
add("ascii_keyword.stl", "solid x\nfacet normal 0 0 1\nouter lop\n", "line 3: expected 'loop', got 'lop'")
add("ascii_no_end.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n", "the file ends before 'endsolid'")
add("ascii_inf.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex inf 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n", "line 5: vertex: non-finite number 'inf'")

# --- OBJ ---
TET_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
add("wrap_index.obj", TET_OBJ + "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 4294967297\n", "line 8: face 4 corner 3: vertex index 4294967297 is out of range (4 vertices in the file, numbered from 1)")
add("huge_index.obj", TET_OBJ + "f 1 3 99999999999999999999\n", "line 5: face 1 corner 3 '99999999999999999999': vertex index '99999999999999999999' is out of range")
add("zero_index.obj", TET_OBJ + "f 0 1 2\n", "line 5: face 1 corner 1 '0': vertex index 0 (OBJ numbers from 1")
add("before_first.obj", TET_OBJ + "f -5 1 2\n", "line 5: face 1 corner 1 '-5': vertex index -5 counts back before the first vertex (4 so far)")
add("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "line 2: vertex 2: non-finite number 'nan'")
add("short_vertex.obj", "v 0 0\n", "line 1: 'v' needs 3 numbers")
add("two_corners.obj", TET_OBJ + "f 1 2\n", "line 5: a face needs at least 3 corners, got 2")
add("no_faces.obj", TET_OBJ, "holds no triangles")
add("texcoord_range.obj", TET_OBJ + "vt 0 0\nf 1/1 3/2 2/1\n", "line 6: face 1 corner 2: texture coordinate index 2 is out of range (1 texture coordinates in the file")
add("normal_range.obj", TET_OBJ + "vn 0 0 1\nf 1//1 3//1 2//3\n", "line 6: face 1 corner 3: normal index 3 is out of range (1 normals in the file")
add("four_parts.obj", TET_OBJ + "f 1/1/1/1 2 3\n", "line 5: face 1 corner 1 '1/1/1/1': more than 3 parts")
add("binary_junk.obj", b"\x00\xff\xfe" * 30 + b"\nf 1 2 3\n", "line 2: face 1 corner 1: vertex index 1 is out of range (0 vertices in the file")
add("missing_index.obj", TET_OBJ + "f /1 2 3\n", "line 5: face 1 corner 1 '/1': vertex index missing")
add("nan_texcoord.obj", TET_OBJ + "vt 0 inf\nf 1 3 2\n", "line 5: texture coordinate 1: non-finite number 'inf'")
add("word_normal.obj", TET_OBJ + "vn 0 0 up\nf 1 3 2\n", "line 5: normal 1: 'up' is not a number")
add("empty.obj", "", "empty.obj': the file is empty")
add("empty.stl", "", "empty.stl': the file is empty")
add("unknown.xyz", "OFF\n", "unknown mesh format '.xyz' (supported: .obj .stl .ply .off)")

# --- solids that are not closed or not 2-manifold (the file is fine, the solid is not) ---
add("open.off", "OFF\n4 3 0\n" + TET_V + "3 0 2 1\n3 0 1 3\n3 0 3 2\n", "mesh is not closed")
add("bowtie.off", "OFF\n7 8 0\n" + TET_V + "-1 0 0\n0 -1 0\n0 0 -1\n" + TET_F + "3 0 4 5\n3 0 6 4\n3 0 5 6\n3 4 6 5\n",
    "the vertex at (0, 0, 0) joins separate fans of triangles")
add("inside_out.off", "OFF\n4 4 0\n" + TET_V + "3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n", "inside out")

# --- session 9: encodings, odd numbers, PLY types and lists, degenerate and out-of-range meshes ---
OFF_TET = "OFF\n4 4 0\n" + TET_V + TET_F
ASTL = "solid t\n" + "".join("facet normal 0 0 0\nouter loop\nvertex %s\nvertex %s\nvertex %s\nendloop\nendfacet\n" % f for f in
                             [("0 0 0", "0 1 0", "1 0 0"), ("0 0 0", "1 0 0", "0 0 1"), ("0 0 0", "0 0 1", "0 1 0"), ("1 0 0", "0 1 0", "0 0 1")]) + "endsolid t\n"
UTF16 = "the file is UTF-16 text (it starts with a UTF-16 byte order mark): save it as UTF-8 or ASCII"
add("utf16.obj", (TET_OBJ + "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n").encode("utf-16"), UTF16)
add("utf16_be.off", b"\xfe\xff" + OFF_TET.encode("utf-16-be"), UTF16)
add("utf16.stl", ASTL.encode("utf-16"), UTF16)
add("bom_only.ply", b"\xef\xbb\xbf", "the file holds only a UTF-8 byte order mark")
add("big_coords.obj", "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n",
    "a vertex at (1.0000000000000001e+300, 0, 0) is beyond +-1e+100 (volumes and normals would overflow)")
add("denormal.off", "OFF\n4 4 0\n0 0 0\n5e-324 0 0\n0 5e-324 0\n0 0 5e-324\n" + TET_F, "is 4.9406564584124654e-324 wide, below 1e-100")
add("degenerate.stl", ASTL.replace("vertex 0 1 0", "vertex 0 0 0", 1), "triangle 1 (counting from 1) has two corners at one point (0, 0, 0): a degenerate triangle")
add("repeat_corner.obj", TET_OBJ + "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\nf 1 1 2\n", "has two corners at one point (0, 0, 0): a degenerate triangle")
add("hex_float.obj", "v 0x1p0 0 0\n", "line 1: vertex 1: '0x1p0' is not a number")
add("comma.obj", "v 0,5 0 0\n", "line 1: vertex 1: '0,5' is not a number")
add("nan_payload.obj", "v nan(123) 0 0\n", "line 1: vertex 1: non-finite number 'nan(123)'")
add("fraction_count.off", "OFF\n4.5 4 0\n", "line 2: count '4.5' is not an integer")
add("fraction_corners.off", "OFF\n4 4 0\n" + TET_V + "3.0 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", "line 7: face 0: corner count '3.0' is not an integer")
def ply_t(vt, ct, it, body, fmt="ascii", nf=4):
    return ("ply\nformat %s 1.0\nelement vertex 4\nproperty %s x\nproperty %s y\nproperty %s z\nelement face %d\n"
            "property list %s %s vertex_indices\nend_header\n" % (fmt, vt, vt, vt, nf, ct, it)) + body
add("char_overflow.ply", ply_t("char", "uchar", "int", "0 0 0\n300 0 0\n0 1 0\n0 0 1\n" + TET_F),
    "line 11: vertex 1 property 'x': 300 is out of range for type char (-128..127)")
add("uchar_negative.ply", ply_t("float", "uchar", "uchar", TET_V + "3 0 2 -1\n"),
    "line 14: face 0 property 'vertex_indices': -1 is out of range for type uchar (0..255)")
add("duplicate_property.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float x\nend_header\n",
    "header line 5: a second property 'x' in element 'vertex'")
add("negative_list.ply", ply_t("float", "int", "int", TET_V + "-3 0 2 1\n"), "line 14: face 0 property 'vertex_indices' has a negative count -3")
add("empty_face.ply", ply_t("float", "uchar", "int", TET_V + TET_F + "0\n", nf=5), "line 18: face 4 has 0 corners, needs at least 3")
add("fraction_index.ply", ply_t("float", "uchar", "int", TET_V + "3 0 2 1.5\n"), "line 14: face 0 property 'vertex_indices': '1.5' is not an integer")
add("version2.ply", ply_t("float", "uchar", "int", "").replace("1.0", "2.0"), "header line 2: unsupported version '2.0'")
add("binary_negative_list.ply", ply_t("float", "int", "int", "", "binary_little_endian", nf=1).encode() + v + struct.pack("<i", -1),
    "byte 219: face 0 property 'vertex_indices' has a negative count -1")

with open("expected.txt", "w") as out:
    out.write("# file<TAB>what its import error must say (written by make.py)\n")
    for name, data, expect in files:
        with open(name, "wb") as f:
            f.write(data)
        out.write(f"{name}\t{expect}\n")
print(len(files), "files")
