#include "reference/shading_inputs.h"

#include "reference/bcsdf_tables.h"

namespace ft {

ShadingInputs bakeShadingInputsCpu(const ShadingParams& params) {
  ShadingInputs in;
  in.params = params;
  in.ambientTable = bakeAmbientTableCpu(params.fabric);
  checkShadingInputs(in);
  return in;
}

}  // namespace ft
