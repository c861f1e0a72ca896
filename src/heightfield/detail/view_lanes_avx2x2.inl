// The lane operations of view_lanes_kernel.inl for AVX2, eight 64-bit lanes in two registers a
// value (lanes 0-3 in lo, 4-7 in hi), each operation the AVX2 one (namespace `one`, from
// view_lanes_avx2.inl) on both halves. The walk waits on its height loads (each turn's cell
// depends on the last turn's height): with eight rays a turn issues eight independent loads, twice
// as many rays move on while the loads are under way. Included by view_trace_simd.cpp inside its
// own namespace after view_lanes_avx2.inl in `one`, with BT_LANES (the target attribute) defined.

constexpr int kLanes = 2 * one::kLanes;
struct I {
    one::I lo, hi;
};
struct D {
    one::D lo, hi;
};
using M = I;

BT_LANES I set1(std::int64_t v) { return {one::set1(v), one::set1(v)}; }
BT_LANES D set1d(double v) { return {one::set1d(v), one::set1d(v)}; }
BT_LANES void store(std::int64_t* p, I v) {
    one::store(p, v.lo);
    one::store(p + one::kLanes, v.hi);
}
BT_LANES void store(double* p, D v) {
    one::store(p, v.lo);
    one::store(p + one::kLanes, v.hi);
}

BT_LANES I add(I a, I b) { return {one::add(a.lo, b.lo), one::add(a.hi, b.hi)}; }
BT_LANES I sub(I a, I b) { return {one::sub(a.lo, b.lo), one::sub(a.hi, b.hi)}; }
BT_LANES I band(I a, I b) { return {one::band(a.lo, b.lo), one::band(a.hi, b.hi)}; }
BT_LANES I bxor(I a, I b) { return {one::bxor(a.lo, b.lo), one::bxor(a.hi, b.hi)}; }
BT_LANES I bor(I a, I b) { return {one::bor(a.lo, b.lo), one::bor(a.hi, b.hi)}; }
/// a * b for a, b below 2^32.
BT_LANES I mul32(I a, I b) { return {one::mul32(a.lo, b.lo), one::mul32(a.hi, b.hi)}; }
/// Shifts by each lane's count (a count of 64 or more gives 0).
BT_LANES I sllv(I a, I n) { return {one::sllv(a.lo, n.lo), one::sllv(a.hi, n.hi)}; }
BT_LANES I srlv(I a, I n) { return {one::srlv(a.lo, n.lo), one::srlv(a.hi, n.hi)}; }
BT_LANES I srl1(I a) { return {one::srl1(a.lo), one::srl1(a.hi)}; }

BT_LANES D addd(D a, D b) { return {one::addd(a.lo, b.lo), one::addd(a.hi, b.hi)}; }
BT_LANES D subd(D a, D b) { return {one::subd(a.lo, b.lo), one::subd(a.hi, b.hi)}; }
BT_LANES D muld(D a, D b) { return {one::muld(a.lo, b.lo), one::muld(a.hi, b.hi)}; }
/// a < b ? a : b, lane by lane (std::min(b, a)).
BT_LANES D mind(D a, D b) { return {one::mind(a.lo, b.lo), one::mind(a.hi, b.hi)}; }

BT_LANES M gt(I a, I b) { return {one::gt(a.lo, b.lo), one::gt(a.hi, b.hi)}; }
BT_LANES M eq(I a, I b) { return {one::eq(a.lo, b.lo), one::eq(a.hi, b.hi)}; }
/// a < b as unsigned 64-bit numbers.
BT_LANES M ult(I a, I b) { return {one::ult(a.lo, b.lo), one::ult(a.hi, b.hi)}; }
BT_LANES M led(D a, D b) { return {one::led(a.lo, b.lo), one::led(a.hi, b.hi)}; }
BT_LANES M ltd(D a, D b) { return {one::ltd(a.lo, b.lo), one::ltd(a.hi, b.hi)}; }
BT_LANES M ged(D a, D b) { return {one::ged(a.lo, b.lo), one::ged(a.hi, b.hi)}; }
BT_LANES M eqd(D a, D b) { return {one::eqd(a.lo, b.lo), one::eqd(a.hi, b.hi)}; }
/// -1 in the lanes where a < 0, else 0.
BT_LANES I negative(D a) { return {one::negative(a.lo), one::negative(a.hi)}; }

BT_LANES M mand(M a, M b) { return {one::mand(a.lo, b.lo), one::mand(a.hi, b.hi)}; }
BT_LANES M mor(M a, M b) { return {one::mor(a.lo, b.lo), one::mor(a.hi, b.hi)}; }
/// ~a & b.
BT_LANES M mandnot(M a, M b) { return {one::mandnot(a.lo, b.lo), one::mandnot(a.hi, b.hi)}; }
/// The lanes of m as the bits of an int (lane j: bit j).
BT_LANES int bits(M m) { return one::bits(m.lo) | one::bits(m.hi) << one::kLanes; }
BT_LANES M mask_of_bits(int b) {
    return {one::mask_of_bits(b & ((1 << one::kLanes) - 1)), one::mask_of_bits(b >> one::kLanes)};
}

/// m ? a : b, lane by lane.
BT_LANES I sel(M m, I a, I b) { return {one::sel(m.lo, a.lo, b.lo), one::sel(m.hi, a.hi, b.hi)}; }
BT_LANES D seld(M m, D a, D b) {
    return {one::seld(m.lo, a.lo, b.lo), one::seld(m.hi, a.hi, b.hi)};
}
/// m ? a : 0.
BT_LANES I keep(M m, I a) { return {one::keep(m.lo, a.lo), one::keep(m.hi, a.hi)}; }
/// std::max and std::min of lanes that hold int32 values (one::max64, one::min64).
BT_LANES I max64(I a, I b) { return {one::max64(a.lo, b.lo), one::max64(a.hi, b.hi)}; }
BT_LANES I min64(I a, I b) { return {one::min64(a.lo, b.lo), one::min64(a.hi, b.hi)}; }

/// v with lane j set to x.
BT_LANES D put(D v, int j, double x) {
    if (j < one::kLanes) {
        return {one::put(v.lo, j, x), v.hi};
    }
    return {v.lo, one::put(v.hi, j - one::kLanes, x)};
}
BT_LANES I put(I v, int j, std::int64_t x) {
    if (j < one::kLanes) {
        return {one::put(v.lo, j, x), v.hi};
    }
    return {v.lo, one::put(v.hi, j - one::kLanes, x)};
}

/// v as doubles, exactly, for 0 <= v < 2^52.
BT_LANES D to_double(I v) { return {one::to_double(v.lo), one::to_double(v.hi)}; }

/// Trailing zero bits of v | 2^40.
BT_LANES I trailing_zeros(I v) { return {one::trailing_zeros(v.lo), one::trailing_zeros(v.hi)}; }

/// one::load_heights of both halves: eight independent loads.
BT_LANES D load_heights(const float* const* address, I entry, I off, M on) {
    return {one::load_heights(address, entry.lo, off.lo, on.lo),
            one::load_heights(address, entry.hi, off.hi, on.hi)};
}
