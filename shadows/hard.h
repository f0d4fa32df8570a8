// Hard shadow map: one depth map from the light's centre, one comparison per receiver with
// slope-scaled bias. V is 0 or 1: the point-light limit of the area light. docs/techniques/hard.md.
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo hardTechnique();
}
