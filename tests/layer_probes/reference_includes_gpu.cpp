// Must NOT compile with ft_reference's include roots: reference/ never sees gpu/.
#include "gpu/gl_objects.h"
