// Must NOT compile with ft_bake's include roots: bake/ (run under mpirun on
// cluster nodes without a GPU) never sees gpu/.
#include "gpu/gl_objects.h"
