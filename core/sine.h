// core/sine.h — a float sine with fixed bits, independent of the C library: the single-precision
// sine of ARM's optimized-routines (MIT licence; Szabolcs Nagy, 2018), evaluated as glibc 2.36
// evaluates it in its x86-64 FMA variant (`__sinf_fma`), so that it returns the bits std::sin
// returned on our machines (all 2^32 inputs compared, docs/determinism.md "The tremor's sine").
// Used by the hand tremor (raster/vertex.cpp), two sines per vertex: the vector form computes
// eight at a time where glibc's is one call per value.
#pragma once

namespace aq {

//! sin(y), the definition: glibc's algorithm step by step in scalar double arithmetic
//! (std::fma where glibc fuses). |error| < 1 ulp.
float sine(float y);

//! out[l] = sine(in[l]) for l = 0..7, bit for bit (AVX2 + FMA where the CPU has them, else the
//! scalar loop). in and out may be the same array.
void sine8(const float* in, float* out);

}  // namespace aq
