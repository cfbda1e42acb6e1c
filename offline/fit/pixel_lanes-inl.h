// SPDX-License-Identifier: MIT
// PixelLanes: one pixel per lane of a Highway vector, with the arithmetic and the ADL-visible
// fmax, fmin and sqrt that proto's templated model code needs, so that the fit's SIMD kernels
// run the model's own basis and angles and cannot drift from their definition. Included by each
// kernel file once per SIMD target (Highway's per-target include guard).

#if defined(VPE_FIT_PIXEL_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef VPE_FIT_PIXEL_LANES_INL_H_
#undef VPE_FIT_PIXEL_LANES_INL_H_
#else
#define VPE_FIT_PIXEL_LANES_INL_H_
#endif

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace vpe::fit::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;

template <class D>
struct PixelLanes {
    using Scalar = hn::TFromD<D>;
    hn::Vec<D> v;

    PixelLanes() = default;
    // NOLINTNEXTLINE: broadcast, like a scalar.
    PixelLanes(Scalar scalar) : v(hn::Set(D(), scalar)) {}
    explicit PixelLanes(hn::Vec<D> vector) : v(vector) {}
};

// Outside the class: GCC does not give friends defined in a class template the target's
// instruction set (#pragma GCC target), and they could not inline Highway's operations. Not
// always_inline: proto's templates were defined outside the target's region, so their own
// instantiations may not inline them (an error for always_inline); the kernels are flattened
// instead, and once inside a kernel every call inlines.
template <class D>
inline PixelLanes<D> operator+(PixelLanes<D> a, PixelLanes<D> b) {
    return PixelLanes<D>(hn::Add(a.v, b.v));
}
template <class D>
inline PixelLanes<D> operator-(PixelLanes<D> a, PixelLanes<D> b) {
    return PixelLanes<D>(hn::Sub(a.v, b.v));
}
template <class D>
inline PixelLanes<D> operator*(PixelLanes<D> a, PixelLanes<D> b) {
    return PixelLanes<D>(hn::Mul(a.v, b.v));
}
template <class D>
inline PixelLanes<D> operator/(PixelLanes<D> a, PixelLanes<D> b) {
    return PixelLanes<D>(hn::Div(a.v, b.v));
}
template <class D>
inline PixelLanes<D> fmax(PixelLanes<D> a, PixelLanes<D> b) {
    return PixelLanes<D>(hn::Max(a.v, b.v));
}
template <class D>
inline PixelLanes<D> fmin(PixelLanes<D> a, PixelLanes<D> b) {
    return PixelLanes<D>(hn::Min(a.v, b.v));
}
template <class D>
inline PixelLanes<D> sqrt(PixelLanes<D> a) {
    return PixelLanes<D>(hn::Sqrt(a.v));
}

}  // namespace vpe::fit::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // VPE_FIT_PIXEL_LANES_INL_H_
