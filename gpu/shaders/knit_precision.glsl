// knit_precision.glsl — GLSL-only include: the float instance of the
// precision-generic common/knit_solver.h (see its header comment).
#define kreal float
#define kvec2 vec2
#define kvec3 vec3
#define kvec4 vec4
#define KR(x) float(x)
