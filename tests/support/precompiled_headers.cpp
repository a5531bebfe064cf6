// tests/support/precompiled_headers.cpp: the owner of the test programs' precompiled header
// (Catch2 and Eigen, tests/CMakeLists.txt). Empty on purpose (Catch2WithMain gives the program its
// main): the header is built once for this program and reused by every test program, and no test
// file's change rebuilds it.
