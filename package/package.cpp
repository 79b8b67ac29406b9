// libwedge.so: every module's objects (linked whole) in one shared library; see CMakeLists.txt.
// This file gives the library a translation unit of its own and nothing else.
