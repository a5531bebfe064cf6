// test_stability_geometry.cpp: placeholder until its tests are written (issue 25).
#include <catch2/catch.hpp>
