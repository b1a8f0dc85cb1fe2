#include "service/machine_lookup.h"

#include "storage/machine_store.h"

namespace thermocomp {

StatusOr<MachineRecord> FindMachine(Session& s, const std::string& name) {
  auto machine = s.machines().Find(name);
  if (!machine) return Status::NotFound("unknown machine '" + name + "'");
  return *machine;
}

StatusOr<MachineAxis> FindMachineAxis(Session& s, const std::string& machine_name,
                                      const std::string& axis_name) {
  auto machine = FindMachine(s, machine_name);
  if (!machine.ok()) return machine.status();
  for (size_t i = 0; i < machine->axes.size(); ++i) {
    if (machine->axes[i].name == axis_name) return MachineAxis{std::move(machine).value(), i};
  }
  return Status::NotFound("unknown axis '" + axis_name + "' on " + machine_name);
}

}  // namespace thermocomp
