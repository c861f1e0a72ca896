// The lane operations for AVX2 (of the ray set-up and shading, and of each half of the walk's
// register pairs, view_lanes_avx2x2.inl): four 64-bit lanes, masks as vectors of all-ones or
// zero lanes. Included by view_trace_simd.cpp inside its own namespace, with BT_LANES (the
// target attribute) defined.

constexpr int kLanes = 4;
using I = __m256i;
using D = __m256d;
using M = __m256i;

BT_LANES I set1(std::int64_t v) { return _mm256_set1_epi64x(v); }
BT_LANES D set1d(double v) { return _mm256_set1_pd(v); }
BT_LANES I load(const std::int64_t* p) {
    return _mm256_load_si256(reinterpret_cast<const __m256i*>(p));
}
BT_LANES D load(const double* p) { return _mm256_load_pd(p); }
BT_LANES void store(std::int64_t* p, I v) { _mm256_store_si256(reinterpret_cast<__m256i*>(p), v); }
BT_LANES void store(double* p, D v) { _mm256_store_pd(p, v); }

BT_LANES I add(I a, I b) { return _mm256_add_epi64(a, b); }
BT_LANES I sub(I a, I b) { return _mm256_sub_epi64(a, b); }
BT_LANES I band(I a, I b) { return _mm256_and_si256(a, b); }
BT_LANES I bxor(I a, I b) { return _mm256_xor_si256(a, b); }
BT_LANES I bor(I a, I b) { return _mm256_or_si256(a, b); }
/// a * b for a, b below 2^32.
BT_LANES I mul32(I a, I b) { return _mm256_mul_epu32(a, b); }
/// Shifts by each lane's count (a count of 64 or more gives 0).
BT_LANES I sllv(I a, I n) { return _mm256_sllv_epi64(a, n); }
BT_LANES I srlv(I a, I n) { return _mm256_srlv_epi64(a, n); }
BT_LANES I srl1(I a) { return _mm256_srli_epi64(a, 1); }

BT_LANES D addd(D a, D b) { return _mm256_add_pd(a, b); }
BT_LANES D subd(D a, D b) { return _mm256_sub_pd(a, b); }
BT_LANES D muld(D a, D b) { return _mm256_mul_pd(a, b); }
BT_LANES D divd(D a, D b) { return _mm256_div_pd(a, b); }
BT_LANES D sqrtd(D a) { return _mm256_sqrt_pd(a); }
/// std::floor, lane by lane.
BT_LANES D floord(D a) { return _mm256_floor_pd(a); }
/// std::trunc, lane by lane.
BT_LANES D truncd(D a) { return _mm256_round_pd(a, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC); }
/// -a (the sign flipped, zeros and infinities included).
BT_LANES D negd(D a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
/// static_cast<float> of the lanes into p[0, kLanes).
BT_LANES void store_floats(float* p, D a) { _mm_storeu_ps(p, _mm256_cvtpd_ps(a)); }
/// static_cast<std::int32_t> (truncation) of the lanes into p[0, kLanes).
BT_LANES void store_ints(std::int32_t* p, D a) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(p), _mm256_cvttpd_epi32(a));
}
/// a < b ? a : b, lane by lane (std::min(b, a)).
BT_LANES D mind(D a, D b) { return _mm256_min_pd(a, b); }

BT_LANES M gt(I a, I b) { return _mm256_cmpgt_epi64(a, b); }
/// a < b as unsigned 64-bit numbers.
BT_LANES M ult(I a, I b) {
    const I sign = _mm256_set1_epi64x(std::numeric_limits<std::int64_t>::min());
    return _mm256_cmpgt_epi64(_mm256_xor_si256(b, sign), _mm256_xor_si256(a, sign));
}
BT_LANES M eq(I a, I b) { return _mm256_cmpeq_epi64(a, b); }
BT_LANES M led(D a, D b) { return _mm256_castpd_si256(_mm256_cmp_pd(a, b, _CMP_LE_OQ)); }
BT_LANES M ltd(D a, D b) { return _mm256_castpd_si256(_mm256_cmp_pd(a, b, _CMP_LT_OQ)); }
/// -1 in the lanes where a < 0, else 0.
BT_LANES I negative(D a) {
    return _mm256_castpd_si256(_mm256_cmp_pd(a, _mm256_setzero_pd(), _CMP_LT_OQ));
}
BT_LANES M ged(D a, D b) { return _mm256_castpd_si256(_mm256_cmp_pd(a, b, _CMP_GE_OQ)); }
BT_LANES M eqd(D a, D b) { return _mm256_castpd_si256(_mm256_cmp_pd(a, b, _CMP_EQ_OQ)); }

BT_LANES M mand(M a, M b) { return _mm256_and_si256(a, b); }
BT_LANES M mor(M a, M b) { return _mm256_or_si256(a, b); }
/// ~a & b.
BT_LANES M mandnot(M a, M b) { return _mm256_andnot_si256(a, b); }
/// The lanes of m as the bits of an int (lane j: bit j).
BT_LANES int bits(M m) { return _mm256_movemask_pd(_mm256_castsi256_pd(m)); }
BT_LANES M mask_of_bits(int b) {
    const I lane = _mm256_setr_epi64x(1, 2, 4, 8);
    return _mm256_cmpeq_epi64(_mm256_and_si256(_mm256_set1_epi64x(b), lane), lane);
}

/// m ? a : b, lane by lane. By the lanes' sign bits (vblendvpd), not the bytes' (vpblendvb):
/// GCC cannot tell that a mask's bytes are all set or all clear, and put a vpcmpgtb before each
/// vpblendvb.
BT_LANES I sel(M m, I a, I b) {
    return _mm256_castpd_si256(_mm256_blendv_pd(_mm256_castsi256_pd(b), _mm256_castsi256_pd(a),
                                                _mm256_castsi256_pd(m)));
}
BT_LANES D seld(M m, D a, D b) { return _mm256_blendv_pd(b, a, _mm256_castsi256_pd(m)); }
/// m ? a : 0.
BT_LANES I keep(M m, I a) { return _mm256_and_si256(m, a); }
/// std::max and std::min of lanes that hold int32 values (sign-extended to 64 bits): those of
/// the halves (a higher half's sign and a lower half's signed value order the lanes alike), one
/// instruction where the 64-bit ones take a comparison and a blend.
BT_LANES I max64(I a, I b) { return _mm256_max_epi32(a, b); }
BT_LANES I min64(I a, I b) { return _mm256_min_epi32(a, b); }

/// v with lane j set to x.
BT_LANES D put(D v, int j, double x) {
    return _mm256_blendv_pd(v, _mm256_set1_pd(x), _mm256_castsi256_pd(mask_of_bits(1 << j)));
}
BT_LANES I put(I v, int j, std::int64_t x) { return sel(mask_of_bits(1 << j), set1(x), v); }

/// v as doubles, exactly, for 0 <= v < 2^52 (AVX2 has no 64-bit integer conversion).
BT_LANES D to_double(I v) {
    const I magic = _mm256_set1_epi64x(0x4330000000000000);
    return _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(v, magic)),
                         _mm256_set1_pd(4503599627370496.0));
}

/// Trailing zero bits of v | 2^40: the exponent of its lowest set bit as a double.
BT_LANES I trailing_zeros(I v) {
    v = _mm256_or_si256(v, set1(std::int64_t{1} << 40));
    const I low = _mm256_and_si256(v, _mm256_sub_epi64(_mm256_setzero_si256(), v));
    const I b = _mm256_castpd_si256(to_double(low));
    return _mm256_sub_epi64(_mm256_srli_epi64(b, 52), set1(1023));
}

/// address[entry][off] in the lanes of `on` where the address is not null, kEmptyHeight
/// elsewhere: scalar loads (the gather instructions are slow on CPUs with the Gather Data
/// Sampling mitigation), the lanes read from a vector store (a vector load of values stored one
/// by one would stall store forwarding). The lanes outside `on` load address[0][0] (a cell of
/// the sections' finest level, or kEmptyHeight where its section is null) instead of a test and
/// a branch each: their heights are of no use.
BT_LANES D load_heights(const float* const* address, I entry, I off, M on) {
    alignas(32) std::int64_t e[kLanes], o[kLanes];
    store(e, keep(on, entry));
    store(o, keep(on, off));
    const auto at = [&](int j) {
        const float* b = address[e[j]];
        return b != nullptr ? b[o[j]] : kEmptyHeight;
    };
    return _mm256_cvtps_pd(_mm_setr_ps(at(0), at(1), at(2), at(3)));
}
