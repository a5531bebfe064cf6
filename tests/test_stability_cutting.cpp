// test_stability_cutting.cpp: placeholder until its tests are written (issue 25).
#include <catch2/catch.hpp>
