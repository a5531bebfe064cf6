// benchmarks/precompiled_headers.cpp: the owner of the benchmark programs' precompiled header
// (Eigen and nlohmann-json, benchmarks/CMakeLists.txt). Empty on purpose: the header is built once
// for this program and reused by every benchmark, and no benchmark's change rebuilds it.
int main() { return 0; }
