// Hard shadow map: one depth map from the light's centre, one comparison per receiver with
// slope-scaled bias. V is 0 or 1: the point-light limit of the area light. docs/techniques/hard.md.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo hardTechnique();
}
