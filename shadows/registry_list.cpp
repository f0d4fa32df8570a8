#include "shadows/registry_list.h"

#include "shadows/backproj.h"
#include "shadows/cssm.h"
#include "shadows/esm.h"
#include "shadows/essm.h"
#include "shadows/evsm.h"
#include "shadows/ground_truth.h"
#include "shadows/hard.h"
#include "shadows/mvr.h"
#include "shadows/occtex.h"
#include "shadows/pcf.h"
#include "shadows/pcss.h"
#include "shadows/pfsvsm.h"
#include "shadows/sssm.h"
#include "shadows/vsm.h"
#include "shadows/vssm.h"
#include "shadows/vwss.h"

namespace penumbra::shadows {

std::vector<TechniqueInfo> allTechniques() {
  return {hardTechnique(), pcfTechnique(), pcssTechnique(), vsmTechnique(), evsm2Technique(), evsm4Technique(),
          esmTechnique(), essmTechnique(),
          savsmTechnique(), vssmTechnique(), cssmTechnique(), pfsvsmTechnique(), backprojTechnique(), occtexTechnique(), sssmTechnique(), mvrTechnique(), vwssTechnique(), referenceTechnique()};
}

}  // namespace penumbra::shadows
