// draw_check.h — what `render` and `knit` check before they draw: the yarn
// buffers they upload and the knot frames the GPU computed from them. A NaN
// there would draw some yarns and silently drop the others (issue 8).
#pragma once
#include <span>
#include <string>

#include "scene/yarn_model.h"

namespace ft {

// Throws std::runtime_error "<model>: yarn <c> knot <k>: ..." (or "point <i>")
// on the first control point or length coordinate that is not finite, or knot
// normal that is not a finite unit vector.
void checkBeforeDrawing(const std::string& model, const YarnBuffers& yarn, std::span<const FrameNormal> frames);

}  // namespace ft
