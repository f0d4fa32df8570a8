// The list the registry is built from (technique.cpp): one entry per technique file pair, in the
// order the CLI, the benchmark and the tests show them. Adding a technique = adding its factory to
// registry_list.cpp.
// Thread-safety: a pure function building a new list.
#pragma once

#include <vector>

#include "shadows/technique.h"

namespace penumbra::shadows {
std::vector<TechniqueInfo> allTechniques();
}
