// Perimeter index t (counter-clockwise from (0, 0); core/include/ngi/seam.h) -> sample of a
// level of resolution r. Shared by the seam welds.
ivec2 perimeterSample(uint t, uint r)
{
    t %= 4u * r;
    if (t <= r) return ivec2(t, 0);
    if (t <= 2u * r) return ivec2(r, t - r);
    if (t <= 3u * r) return ivec2(3u * r - t, r);
    return ivec2(0, 4u * r - t);
}
