// The enclosure measure (scene/enclosure.h, docs/lpv.md "Closed scenes") against closed forms: an open-top
// box under a vertical sun scatters from its lit floor only, so the escaped share is the view factor of
// the floor to the opening (two directly opposed squares, Howell's catalogue C-11, in double); a closed
// box keeps everything; unlit surfaces do not count while something is lit.
#include "scene/enclosure.h"
#include "test_enclosure_scenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

using namespace rtgi;
using namespace rtgi::test;

namespace {
// View factor between directly opposed parallel rectangles a x b at distance c.
double opposedRectangles(double a, double b, double c) {
    const double X = a / c, Y = b / c;
    const double X2 = 1 + X * X, Y2 = 1 + Y * Y;
    return 2.0 / (std::numbers::pi * X * Y) *
           (0.5 * std::log(X2 * Y2 / (X2 + Y2 - 1)) + X * std::sqrt(Y2) * std::atan(X / std::sqrt(Y2)) +
            Y * std::sqrt(X2) * std::atan(Y / std::sqrt(X2)) - X * std::atan(X) - Y * std::atan(Y));
}
}  // namespace

TEST_CASE("enclosure: an open-top box under a vertical sun lets out its floor's view factor to the opening") {
    CHECK(opposedRectangles(1, 1, 1) == doctest::Approx(0.19982).epsilon(1e-4));  // the catalogue's value
    for (float h : {1.0f, 0.5f}) {
        CAPTURE(h);
        Scene s = enclosureBox(1.0f, h, false);
        s.lights.push_back(enclosureSun());
        // A large unlit surface whose every ray escapes: it must not count (weights are direct irradiance).
        // (4 m², four times the floor: area weights would give ~0.8.)
        addQuad(s, {-1, -5, -1}, {1, -5, -1}, {1, -5, 1}, {-1, -5, 1}, 0);  // normal -y, away from the sun
        const Enclosure e = measureEnclosure(s, 16384, 7);
        const double F = opposedRectangles(1, 1, h);
        CHECK(e.lit);
        CHECK(e.rays == 16384);  // drawn until so many points were lit
        // Binomial standard deviation at 16384 rays: at most 0.004.
        CAPTURE(e.escaped);
        CAPTURE(F);
        CHECK(std::abs(e.escaped - F) < 0.015);
    }
}

TEST_CASE("enclosure: a closed box keeps all light; with no light, points weigh by area") {
    const Scene closed = enclosureRoom();
    const Enclosure c = measureEnclosure(closed, 4096, 3);
    CHECK(c.lit);
    CHECK(c.escaped == 0.0);

    Scene plane;
    plane.materials.push_back(Material{});
    addQuad(plane, {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, 0);
    const Enclosure p = measureEnclosure(plane, 1024, 3);
    CHECK_FALSE(p.lit);
    CHECK(p.rays == 16 * 1024);  // every point drawn counts by area
    CHECK(p.escaped == 1.0);

    Scene empty;
    CHECK(measureEnclosure(empty).rays == 0);
}

TEST_CASE("enclosure: a sun that only reaches the outside of a closed box sees an open scene") {
    // The box's quads face inward; an outward-facing roof above it takes the sun and scatters upwards.
    Scene s = enclosureBox(1.0f, 1.0f, true);
    s.lights.push_back(enclosureSun());
    addQuad(s, {-1, 2, -1}, {-1, 2, 2}, {2, 2, 2}, {2, 2, -1}, 0);  // normal +y, lit
    const Enclosure e = measureEnclosure(s, 4096, 5);
    CHECK(e.lit);
    CHECK(e.escaped == 1.0);
}
