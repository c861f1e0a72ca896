// The lane operations of view_lanes_kernel.inl for AVX-512 (F, DQ, CD): eight 64-bit lanes,
// masks in mask registers. Included by view_trace_simd.cpp inside its own namespace, with
// BT_LANES (the target attribute) defined.

constexpr int kLanes = 8;
using I = __m512i;
using D = __m512d;
using M = __mmask8;

BT_LANES I set1(std::int64_t v) { return _mm512_set1_epi64(v); }
BT_LANES D set1d(double v) { return _mm512_set1_pd(v); }
BT_LANES I load(const std::int64_t* p) { return _mm512_load_si512(p); }
BT_LANES D load(const double* p) { return _mm512_load_pd(p); }
BT_LANES void store(std::int64_t* p, I v) { _mm512_store_si512(p, v); }
BT_LANES void store(double* p, D v) { _mm512_store_pd(p, v); }

BT_LANES I add(I a, I b) { return _mm512_add_epi64(a, b); }
BT_LANES I sub(I a, I b) { return _mm512_sub_epi64(a, b); }
BT_LANES I band(I a, I b) { return _mm512_and_si512(a, b); }
BT_LANES I bxor(I a, I b) { return _mm512_xor_si512(a, b); }
BT_LANES I bor(I a, I b) { return _mm512_or_si512(a, b); }
/// a * b for a, b below 2^32.
BT_LANES I mul32(I a, I b) { return _mm512_mul_epu32(a, b); }
/// Shifts by each lane's count (a count of 64 or more gives 0).
BT_LANES I sllv(I a, I n) { return _mm512_sllv_epi64(a, n); }
BT_LANES I srlv(I a, I n) { return _mm512_srlv_epi64(a, n); }
BT_LANES I srl1(I a) { return _mm512_srli_epi64(a, 1); }

BT_LANES D addd(D a, D b) { return _mm512_add_pd(a, b); }
BT_LANES D subd(D a, D b) { return _mm512_sub_pd(a, b); }
/// a * b rounded on its own: never fused with an addition into an FMA (AVX-512 implies FMA, and
/// GCC fuses the plain vector product), so that oz + dz * t is the scalar traversal's double.
BT_LANES D muld(D a, D b) { return _mm512_mul_round_pd(a, b, _MM_FROUND_CUR_DIRECTION); }
BT_LANES D divd(D a, D b) { return _mm512_div_pd(a, b); }
BT_LANES D sqrtd(D a) { return _mm512_sqrt_pd(a); }
/// std::floor, lane by lane.
BT_LANES D floord(D a) {
    return _mm512_roundscale_pd(a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
}
/// a < b ? a : b, lane by lane (std::min(b, a)).
BT_LANES D mind(D a, D b) { return _mm512_min_pd(a, b); }
/// std::trunc, lane by lane.
BT_LANES D truncd(D a) {
    return _mm512_roundscale_pd(a, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
}
/// -a (the sign flipped, zeros and infinities included).
BT_LANES D negd(D a) { return _mm512_xor_pd(a, _mm512_set1_pd(-0.0)); }
/// static_cast<float> of the lanes into p[0, kLanes).
BT_LANES void store_floats(float* p, D a) { _mm256_storeu_ps(p, _mm512_cvtpd_ps(a)); }
/// static_cast<std::int32_t> (truncation) of the lanes into p[0, kLanes).
BT_LANES void store_ints(std::int32_t* p, D a) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), _mm512_cvttpd_epi32(a));
}

BT_LANES M gt(I a, I b) { return _mm512_cmpgt_epi64_mask(a, b); }
/// a < b as unsigned 64-bit numbers.
BT_LANES M ult(I a, I b) { return _mm512_cmplt_epu64_mask(a, b); }
BT_LANES M eq(I a, I b) { return _mm512_cmpeq_epi64_mask(a, b); }
BT_LANES M led(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
BT_LANES M ltd(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
/// -1 in the lanes where a < 0, else 0.
BT_LANES I negative(D a) {
    return _mm512_movm_epi64(_mm512_cmp_pd_mask(a, _mm512_setzero_pd(), _CMP_LT_OQ));
}
BT_LANES M ged(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }
BT_LANES M eqd(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_EQ_OQ); }

BT_LANES M mand(M a, M b) { return static_cast<M>(a & b); }
BT_LANES M mor(M a, M b) { return static_cast<M>(a | b); }
/// ~a & b.
BT_LANES M mandnot(M a, M b) { return static_cast<M>(~a & b); }
/// The lanes of m as the bits of an int (lane j: bit j).
BT_LANES int bits(M m) { return static_cast<int>(m); }
BT_LANES M mask_of_bits(int b) { return static_cast<M>(b); }

/// m ? a : b, lane by lane.
BT_LANES I sel(M m, I a, I b) { return _mm512_mask_blend_epi64(m, b, a); }
BT_LANES D seld(M m, D a, D b) { return _mm512_mask_blend_pd(m, b, a); }
/// m ? a : 0.
BT_LANES I keep(M m, I a) { return _mm512_maskz_mov_epi64(m, a); }
BT_LANES I max64(I a, I b) { return _mm512_max_epi64(a, b); }
BT_LANES I min64(I a, I b) { return _mm512_min_epi64(a, b); }

/// v with lane j set to x.
BT_LANES D put(D v, int j, double x) {
    return _mm512_mask_broadcastsd_pd(v, static_cast<__mmask8>(1u << j), _mm_set_sd(x));
}
BT_LANES I put(I v, int j, std::int64_t x) {
    return _mm512_mask_set1_epi64(v, static_cast<__mmask8>(1u << j), x);
}

/// v as doubles, exactly, for |v| < 2^53.
BT_LANES D to_double(I v) { return _mm512_cvtepi64_pd(v); }

/// Trailing zero bits of v | 2^40: 63 - the leading zeros of its lowest set bit.
BT_LANES I trailing_zeros(I v) {
    v = _mm512_or_si512(v, set1(std::int64_t{1} << 40));
    const I low = _mm512_and_si512(v, _mm512_sub_epi64(_mm512_setzero_si512(), v));
    return _mm512_sub_epi64(set1(63), _mm512_lzcnt_epi64(low));
}

/// address[entry][off] in the lanes of `on` (bits) where the address is not null, kEmptyHeight
/// elsewhere: scalar loads (the gather instructions are slow on CPUs with the Gather Data
/// Sampling mitigation), the lanes read from a vector store.
BT_LANES D load_heights(const float* const* address, I entry, I off, M on) {
    alignas(64) std::int64_t e[kLanes], o[kLanes];
    store(e, entry);
    store(o, off);
    const auto at = [&](int j) {
        const float* b = (on & (1 << j)) != 0 ? address[e[j]] : nullptr;
        return b != nullptr ? b[o[j]] : kEmptyHeight;
    };
    return _mm512_cvtps_pd(
        _mm256_setr_ps(at(0), at(1), at(2), at(3), at(4), at(5), at(6), at(7)));
}
