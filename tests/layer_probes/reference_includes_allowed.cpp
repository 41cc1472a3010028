// Must compile with ft_reference's include roots (the control for the failures).
#include "common/prelude.h"
#include "knit/knit_problem.h"
#include "reference/fiber_reference.h"
#include "scene/yarn_model.h"
