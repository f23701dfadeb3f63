// ngi offline (internal): angle and area formulas of one triangle from its side lengths,
// written to stay accurate for needle and cap triangles (Kahan's ordering for the area).
#pragma once

#include <algorithm>
#include <cmath>

namespace ngi::detail {

// Area of a triangle with side lengths a, b, c (Kahan's stable Heron). 0 when degenerate.
inline double triangleAreaFromLengths(double a, double b, double c)
{
    if (a < b) std::swap(a, b);
    if (b < c) std::swap(b, c);
    if (a < b) std::swap(a, b);
    const double s = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
    return s > 0.0 ? 0.25 * std::sqrt(s) : 0.0;
}

// True when a, b, c satisfy the strict triangle inequalities with relative margin `eps`.
inline bool satisfiesTriangleInequality(double a, double b, double c, double eps = 1e-12)
{
    const double m = eps * (a + b + c);
    return a + b > c + m && b + c > a + m && a + c > b + m;
}

// Angle opposite side a (sides b, c adjacent), from lengths: atan2(4 area, b^2 + c^2 - a^2).
inline double angleFromLengths(double a, double b, double c, double area)
{
    return std::atan2(4.0 * area, b * b + c * c - a * a);
}

// Cotangent of the angle opposite side a: (b^2 + c^2 - a^2) / (4 area).
inline double cotangentFromLengths(double a, double b, double c, double area)
{
    return (b * b + c * c - a * a) / (4.0 * area);
}

}  // namespace ngi::detail
