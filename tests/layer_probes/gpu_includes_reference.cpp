// Must NOT compile with ft_gpu's include roots: gpu/ never sees reference/.
#include "reference/fiber_reference.h"
