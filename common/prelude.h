// prelude.h — makes every header in common/ compile both as C++20 (with GLM)
// and as GLSL 4.50. Include it first; the GPU shader loader injects it too.
//
// Rules for common/ (so both compilers accept the same text):
//  * no STL, templates, references, swizzles or function overloading on
//    return type; functions are pure and return values (GLSL has no pointers);
//  * mark functions FT_FUNC (inline in C++, nothing in GLSL); FT_INLINE for
//    small helpers of hot loops that take structs by value (forced inline in
//    C++, where an outlined call copies the struct; GLSL inlines everything);
//  * float literals carry an `f` suffix and unsigned ones a `u` suffix;
//  * layout asserts (FT_ASSERT_OFFSET/FT_ASSERT_SIZE) take no trailing `;`
//    (GLSL rejects an empty declaration);
//  * use FT_PRECISE on values whose rounding decides something discrete
//    (a period index, a LoD count): GLSL `precise` forbids FMA contraction and
//    reassociation; the C++ side is compiled with -ffp-contract=off;
//  * math needed in double on the CPU and float on the GPU is written once in
//    the types kreal/kvec2..4 and KR(x), without an include guard, and
//    instantiated by its includer (common/knit_solver.h says how).
#ifndef FT_PRELUDE_H
#define FT_PRELUDE_H

#ifdef __cplusplus
#define GLM_FORCE_XYZW_ONLY  // no swizzle unions: keeps glm types trivially copyable
#include <glm/glm.hpp>
#include <cstddef>
#include <cstdint>
#define FT_FUNC inline
#define FT_INLINE inline __attribute__((always_inline))
#define FT_PRECISE
#define FT_STATIC_ASSERT(cond, msg) static_assert(cond, msg);
#define FT_ASSERT_OFFSET(type, member, off) \
  static_assert(offsetof(type, member) == (off), #type "." #member " offset must match GLSL");
#define FT_ASSERT_SIZE(type, size) static_assert(sizeof(type) == (size), #type " size must match GLSL");
namespace ft {
using glm::vec2; using glm::vec3; using glm::vec4;
using glm::uvec2; using glm::uvec3; using glm::uvec4;
using glm::ivec2; using glm::ivec4; using glm::mat4;
using glm::abs; using glm::clamp; using glm::cos; using glm::cross; using glm::dot; using glm::floor;
using glm::fract; using glm::length; using glm::max; using glm::min; using glm::mix; using glm::sin;
using glm::sqrt; using glm::exp; using glm::log; using glm::ceil; using glm::atan;
using glm::asin; using glm::acos; using glm::pow;
typedef std::uint32_t uint;
}  // namespace ft
#define FT_NAMESPACE_BEGIN namespace ft {
#define FT_NAMESPACE_END }
#else  // GLSL
#define FT_FUNC
#define FT_INLINE
#define FT_PRECISE precise
#define FT_STATIC_ASSERT(cond, msg)
#define FT_ASSERT_OFFSET(type, member, off)
#define FT_ASSERT_SIZE(type, size)
#define FT_NAMESPACE_BEGIN
#define FT_NAMESPACE_END
#endif

FT_NAMESPACE_BEGIN
const float FT_PI = 3.14159265358979323846f;
const float FT_TWO_PI = 6.28318530717958647692f;
const float FT_INV_PI = 0.318309886183790671538f;      // 1/π, rounded to float by both compilers alike
const float FT_INV_TWO_PI = 0.159154943091895335769f;  // 1/(2π)

// sqrt-based normalize: GLSL's normalize may use an approximate inversesqrt,
// which would make the two sides drift apart along a long frame propagation.
FT_FUNC vec3 ftNormalize(vec3 v) { return v / sqrt(dot(v, v)); }
FT_NAMESPACE_END

#endif  // FT_PRELUDE_H
