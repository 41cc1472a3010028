// Must compile with ft_gpu's include roots (the control for the failures).
#include "common/prelude.h"
#include "gpu/fiber_gpu.h"
#include "gpu/knit_gpu.h"
#include "scene/fiber_input.h"
