// Loading the continuum module with dlopen (fem_module_loader.h).
#include "fem_module_loader.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "grainlift/shared/errors.h"

namespace grainlift::app {
namespace {

const continuum::FemModule* loaded = nullptr;

/// Where the module may be: beside the command as built or installed, then the build tree.
std::vector<std::string> module_candidates() {
  std::vector<std::string> paths;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec)
    paths.push_back((exe.parent_path() / GRAINLIFT_FEM_MODULE_RELATIVE_PATH).lexically_normal());
  if (paths.empty() || paths.front() != GRAINLIFT_FEM_MODULE_BUILD_PATH)
    paths.push_back(GRAINLIFT_FEM_MODULE_BUILD_PATH);
  return paths;
}

}  // namespace

const continuum::FemModule& fem_module() {
  if (loaded) return *loaded;
  std::string reasons;
  for (const std::string& path : module_candidates()) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
      reasons += fmt::format("\n  {}: no such file", path);
      continue;
    }
    // RTLD_GLOBAL is not needed: the module finds the command's own symbols (it is linked
    // with exported symbols), and nothing else looks into the module. RTLD_LAZY: binding
    // every function of deal.II and its libraries up front (RTLD_NOW) costs 0.1-0.2 s more.
    void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      reasons += fmt::format("\n  {}: {}", path, why ? why : "dlopen failed");
      continue;
    }
    using Entry = const continuum::FemModule* (*)();
    auto entry = reinterpret_cast<Entry>(dlsym(handle, "grainlift_fem_module"));
    const continuum::FemModule* m = entry ? entry() : nullptr;
    if (!m || m->version != continuum::kFemModuleVersion) {
      reasons += fmt::format("\n  {}: {}", path,
                             m ? fmt::format("module version {}, this command needs {}",
                                             m->version, continuum::kFemModuleVersion)
                               : std::string("no grainlift_fem_module() in it"));
      dlclose(handle);
      continue;
    }
    loaded = m;  // kept loaded for the rest of the process (deal.II cannot be unloaded)
    return *loaded;
  }
  throw RunError(fmt::format(
      "the continuum solver (fem) could not be loaded; it is the module grainlift_fem.so that "
      "the build puts in build/{0} and `cmake --install` in PREFIX/{0} (rebuild or reinstall "
      "grainlift); tried:{1}",
      GRAINLIFT_FEM_MODULE_DIR, reasons));
}

const continuum::FemModule* fem_module_if_loaded() { return loaded; }

bool started_by_mpi_launcher() {
  // the number of ranks as Open MPI's mpirun, MPICH's Hydra (PMI) and Slurm's srun give it;
  // one rank needs no MPI before its first continuum run
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "SLURM_STEP_NUM_TASKS"}) {
    const char* v = std::getenv(var);
    if (v && std::atoi(v) > 1) return true;
  }
  return false;
}

}  // namespace grainlift::app
