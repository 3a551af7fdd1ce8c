#include "gl/profiler.h"

#include <doctest/doctest.h>

using namespace rtgi;

TEST_CASE("timing statistics: median, min, max, mean") {
    auto s = gl::computeStats({4, 1, 3, 2});
    CHECK(s.median == doctest::Approx(2.5));
    CHECK(s.min == 1);
    CHECK(s.max == 4);
    CHECK(s.mean == doctest::Approx(2.5));
    auto t = gl::computeStats({5, 1, 3});
    CHECK(t.median == 3);
}
