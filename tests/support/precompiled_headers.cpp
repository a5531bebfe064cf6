// tests/support/precompiled_headers.cpp: the owner of the test programs' precompiled header
// (Catch2 and Eigen, tests/CMakeLists.txt). Empty on purpose: the header is built once for this
// target and reused by every test program, and no test file's change rebuilds it.
