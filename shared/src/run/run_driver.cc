#include "grainlift/shared/run/run_driver.h"

#include <fmt/format.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <mutex>
#include <optional>

#include "grainlift/shared/results/atomic_file.h"
#include "grainlift/shared/results/compare.h"
#include "grainlift/shared/results/derived_quantities.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/run/interrupt.h"
#include "grainlift/shared/run/output_lock.h"
#include "grainlift/shared/run/side_by_side.h"
#include "grainlift/shared/results/json_writer.h"
#include "grainlift/shared/results/result_file.h"

#ifndef GRAINLIFT_VERSION
#define GRAINLIFT_VERSION "0.0.0"
#endif
#if __has_include("git_revision.h")  // generated at every build (cmake/git_revision.cmake)
#include "git_revision.h"
#endif
#ifndef GRAINLIFT_GIT_REVISION
#define GRAINLIFT_GIT_REVISION "unknown"
#endif

namespace grainlift {

std::string grainlift_version() { return GRAINLIFT_VERSION; }
std::string grainlift_git_revision() { return GRAINLIFT_GIT_REVISION; }

namespace {

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

JsonObject summary_object(const RunResult& r) {
  JsonObject o;
  if (r.means) {
    o.add("drag", r.means->drag);
    o.add("lift", r.means->lift);
    o.add("torque", r.means->torque);
    o.add("drag_stderr", r.means->drag_stderr);
    o.add("lift_stderr", r.means->lift_stderr);
    o.add("torque_stderr", r.means->torque_stderr);
    if (r.means->contacts) o.add("contacts", *r.means->contacts);
    o.add("samples", static_cast<long long>(r.means->samples));
  }
  const DerivedQuantities q = derive(r);
  if (q.lift_over_drag) o.add("lift_over_drag", *q.lift_over_drag);
  o.add("spin_ratio", q.spin_ratio);
  if (q.buoyancy) {
    o.add("buoyancy", *q.buoyancy);
    o.add("lift_over_buoyancy", *q.lift_over_buoyancy);
  }
  if (q.drag_coefficient) {
    o.add("equivalent_depth", r.geometry.equivalent_depth);
    o.add("drag_coefficient", *q.drag_coefficient);
  }
  if (r.lid) {
    o.add("lid_pressure_target", r.lid->target);
    o.add("lid_pressure_mean", r.lid->mean);
    o.add("lid_pressure_stderr", r.lid->mean_stderr);
  }
  if (r.bed) {
    o.add("bed_contacts_per_grain", r.bed->contacts_per_grain);
    o.add("bed_rattler_fraction", r.bed->rattler_fraction);
  }
  if (r.far_field) {
    o.add("far_field_pressure", r.far_field->mean);
    o.add("far_field_pressure_stderr", r.far_field->mean_stderr);
  }
  o.add("pressure_scale", r.geometry.pressure_scale);
  o.add("wall_seconds", r.meta.wall_seconds);
  o.add("threads", r.meta.threads);
  if (const auto it = r.diagnostics.texts.find("simd"); it != r.diagnostics.texts.end())
    o.add("simd", it->second);  // the DEM's vector target (scalar, avx2, avx512, ...)
  o.add("case_hash", r.meta.case_hash);
  if (r.meta.partial) o.add("partial", true);
  if (!r.meta.notes.empty()) o.add("notes", r.meta.notes);
  return o;
}

}  // namespace

std::string summary_object_json(const RunResult& r) { return summary_object(r).str(2); }

void write_summary(const std::string& out_dir, const std::string& case_hash) {
  JsonObject root;
  std::optional<RunResult> dem, fem;
  for (const char* solver : {"dem", "fem"}) {
    const std::string path = out_dir + "/" + solver + ".h5";
    if (!std::filesystem::exists(path)) continue;
    RunResult r;
    try {
      r = read_result(path);
    } catch (const InputError&) {
      continue;  // not ours or unreadable: leave it out of the summary
    }
    if (r.meta.case_hash != case_hash) continue;
    root.add(solver, summary_object(r));
    (std::string(solver) == "dem" ? dem : fem) = std::move(r);
  }
  if (dem && fem) {
    // DEM is the reference (A) of the comparison.
    root.add("compare", comparison_object(compare_results(*dem, *fem)));
  }
  write_text_atomically(out_dir + "/summary.json", root.str(2) + "\n");
}

namespace {
/// The driver's part of a result: who made it, when, from which case.
void stamp(RunResult& r, const Case& c, const std::string& solver, const RunOptions& options,
           std::chrono::steady_clock::time_point started) {
  r.meta.solver = solver;
  r.meta.grainlift_version = grainlift_version();
  r.meta.git_revision = grainlift_git_revision();
  r.meta.threads = options.threads;
  r.meta.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  r.meta.created_utc = utc_now();
  r.meta.case_text = c.source.text;
  std::string overrides;
  for (const auto& o : c.source.overrides) overrides += o + "\n";
  r.meta.case_overrides = overrides;
  r.meta.case_hash = c.source.hash;
  r.meta.case_path = c.source.path;
}

void write_solver_files(const std::string& out_dir, const std::string& solver, const RunResult& r) {
  write_result(out_dir + "/" + solver + ".h5", r);
  write_fields_xdmf(out_dir + "/" + solver + "_fields.xmf", solver + ".h5", r);
}

/// The --out folder, made again with a warning when it was removed while a solver ran.
void remake_if_removed(const std::string& out_dir, ProgressReporter& progress) {
  if (std::filesystem::exists(out_dir)) return;
  progress.message(fmt::format("warning: {} was removed during the run; made again for the "
                               "result",
                               out_dir));
  make_directories(out_dir);
}

/// The solver's files in @p out_dir; when they cannot be written there (a full disk, a
/// read-only folder), in a folder of the system's temporary directory instead, and the
/// RunError (exit 1) says where they are. The result of a long run is never lost to a write.
void write_solver_files_or_rescue(const std::string& out_dir, const std::string& solver,
                                  const RunResult& r, const std::string& case_hash) {
  try {
    write_solver_files(out_dir, solver, r);
  } catch (const RunError& e) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path rescue = fs::temp_directory_path(ec) /
                            fmt::format("grainlift-{}-{}", case_hash.substr(0, 12), ::getpid());
    try {
      make_directories(rescue.string());
      write_solver_files(rescue.string(), solver, r);
    } catch (const std::exception&) {
      throw e;  // nowhere to write: the first cause
    }
    throw RunError(fmt::format("{}\nThe result was written instead to {}/{}.h5: copy it to where "
                               "you want it.", e.what(), rescue.string(), solver));
  }
}

/// One solver's run: its progress, partial results and files; @p io serialises the driver's
/// writes and reads of the result files (HDF5 is not thread-safe) when solvers run side by side.
RunResult run_one(const Case& c, const SolverEntry& solver, const RunOptions& options,
                  bool own_line, std::mutex& io) {
  ProgressReporter progress(solver.name, options.progress, own_line);
  const auto t0 = std::chrono::steady_clock::now();
  RunOptions solver_options = options;
  if (options.writer) {
    solver_options.save_partial = [&](RunResult partial) {
      stamp(partial, c, solver.name, options, t0);
      partial.meta.partial = true;
      // an intermediate result that cannot be written is a warning: the solve goes on
      try {
        const std::lock_guard<std::mutex> lock(io);
        remake_if_removed(options.out_dir, progress);
        write_solver_files(options.out_dir, solver.name, partial);
        write_summary(options.out_dir, c.source.hash);
      } catch (const RunError& e) {
        progress.message(fmt::format("warning: intermediate result not written, the run "
                                     "goes on: {}", e.what()));
      }
    };
  }
  RunResult r = solver.run(c, solver_options, progress);
  stamp(r, c, solver.name, options, t0);
  if (options.writer) {
    const std::lock_guard<std::mutex> lock(io);
    remake_if_removed(options.out_dir, progress);
    write_solver_files_or_rescue(options.out_dir, solver.name, r, c.source.hash);
  }
  progress.finish();
  return r;
}
}  // namespace

std::vector<RunResult> run_solvers(const Case& c, const std::vector<SolverEntry>& solvers,
                                   const RunOptions& options) {
  std::optional<OutputLock> lock;  // one writer per folder (output_lock.h)
  if (options.writer) {
    make_directories(options.out_dir);
    lock.emplace(options.out_dir);
  }
  std::mutex io;
  std::vector<RunResult> results;
  if (options.side_by_side && solvers.size() > 1) {
    // Every solver on a thread of its own, the last (the continuum, listed last) on this one,
    // where it makes its MPI calls (side_by_side.h). A solver that fails does not stop the
    // others: their files are written, the summary lists them, and the first failure in the
    // solvers' order propagates.
    std::vector<std::optional<RunResult>> done(solvers.size());
    auto finished = [&] {
      for (auto& r : done)
        if (r) results.push_back(std::move(*r));
      if (options.writer && !results.empty()) write_summary(options.out_dir, c.source.hash);
    };
    try {
      side_by_side(
          solvers.size(), static_cast<int>(solvers.size()),
          [&](std::size_t k) { done[k] = run_one(c, solvers[k], options, false, io); },
          [](std::size_t) {});
    } catch (...) {
      finished();
      throw;
    }
    finished();
    return results;
  }
  for (const auto& solver : solvers) {
    try {
      results.push_back(run_one(c, solver, options, true, io));
    } catch (...) {
      // The solvers that finished keep their files; the summary lists them before the
      // failure propagates (exit code 1 or 2).
      if (!results.empty() && options.writer) write_summary(options.out_dir, c.source.hash);
      throw;
    }
    if (interrupt_signal()) break;  // the next solvers do not start
  }
  if (options.writer) write_summary(options.out_dir, c.source.hash);
  return results;
}

}  // namespace grainlift
