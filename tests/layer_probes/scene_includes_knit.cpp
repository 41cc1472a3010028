// Must NOT compile with ft_scene's include roots: scene/ sees common/ only.
#include "knit/stitch_mesh.h"
