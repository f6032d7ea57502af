# One libFuzzer target per reader: fuzz_<name>. Read by tests/fuzz/CMakeLists.txt
# (which builds them) and tests/CMakeLists.txt (which runs them); keep in step
# with kTargets in fuzz_reader.cpp and with make_corpus.py.
set(VDMESH_FUZZ_TARGETS off stl obj ply msh vtk vtu tetgen poly smesh mesh meshb inp gz)
