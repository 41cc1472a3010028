// default_scene.h — the built-in scene: a small woven patch plus curves that
// exercise every code path (closed loop, straight vertical piece where a
// fixed-up-vector frame would break, an open cubic Bézier curve).
#pragma once
#include "scene/yarn_model.h"

namespace ft {

YarnModel makeDefaultScene();

}  // namespace ft
