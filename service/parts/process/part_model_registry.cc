// The registry of part-error model types (part_model.h): a new type is a
// PartModelType of its own files and one line here.
#include "service/parts/process/part_model.h"
#include "service/parts/process/part_model_types.h"

namespace thermocomp {

const std::vector<const PartModelType*>& PartModelTypes() {
  static const QuadraticPartType quadratic;
  static const NeuralPartType neural;
  static const std::vector<const PartModelType*> types = {&quadratic, &neural};
  return types;
}

const PartModelType* FindPartModelType(const std::string& name) {
  for (const PartModelType* t : PartModelTypes()) {
    if (t->name() == name) return t;
  }
  return nullptr;
}

}  // namespace thermocomp
