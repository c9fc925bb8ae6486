#include "commands.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <new>

#include "grainlift/shared/results/atomic_file.h"
#ifdef GRAINLIFT_HAVE_DEM
#include "grainlift/dem/step/vector_kernels.h"
#endif
#include "grainlift/shared/case/case_keys.h"
#include "grainlift/shared/case/case_loader.h"
#include "grainlift/shared/results/compare.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/run/interrupt.h"
#include "grainlift/shared/results/result_file.h"
#include "grainlift/shared/rheology/rheology_cache.h"
#include "grainlift/shared/rheology/rheology_file.h"

namespace grainlift::app {
namespace {

const std::map<std::string, std::string> known_solvers = {
    {"dem", "discrete element method, 2D frictional disks (dem/)"},
    {"fem", "finite-element mu(I) continuum, deal.II (continuum/)"}};

/// Resolves --solver dem|fem|both into entries; unknown or unbuilt solvers are InputErrors.
std::vector<SolverEntry> pick_solvers(const std::string& which) {
  const auto built = available_solvers();
  std::vector<std::string> names;
  if (which == "both") names = {"dem", "fem"};
  else names = {which};
  std::vector<SolverEntry> out;
  for (const auto& n : names) {
    auto it = std::find_if(built.begin(), built.end(), [&](const auto& s) { return s.name == n; });
    if (it == built.end()) {
      if (known_solvers.count(n))
        throw InputError(fmt::format(
            "solver '{}' ({}) is not available in this build of grainlift yet; available: {}", n,
            known_solvers.at(n), built.empty() ? std::string("none") : [&] {
              std::string s;
              for (const auto& b : built) s += (s.empty() ? "" : ", ") + b.name;
              return s;
            }()));
      throw InputError(fmt::format("unknown solver '{}' (accepted: dem, fem, both)", n));
    }
    out.push_back(*it);
  }
  return start_solvers(std::move(out));
}

std::string default_out_dir(const std::string& case_path) {
  std::filesystem::path p(case_path);
  std::string name = p.parent_path().filename().string();
  if (name.empty() || name == "." || name == "cases") name = p.stem().string();
  else if (p.stem() != name) name += "-" + p.stem().string();
  return "out/" + name;
}

struct RunArgs {
  std::string case_path, solver = "both", out;
  std::vector<std::string> sets;
  int threads = 1;
  int replicas = 1;
  bool quiet = false;
  std::string resume;  ///< run --resume DIR
};

void print_results(const std::vector<RunResult>& results, const std::string& out) {
  for (const auto& r : results) {
    if (!r.means) continue;
    const auto& m = *r.means;
    auto se = [](const std::optional<double>& s) {
      return s ? fmt::format(" ± {:.3g}", *s) : std::string();
    };
    fmt::print("{:>4}: drag {:.6g}{} N/m   lift {:.6g}{} N/m   torque {:.6g}{} N   ({})\n",
               r.meta.solver, m.drag, se(m.drag_stderr), m.lift, se(m.lift_stderr), m.torque,
               se(m.torque_stderr), format_duration(r.meta.wall_seconds));
  }
  fmt::print("results: {}/  (summary.json", out);
  for (const auto& r : results) fmt::print(", {}.h5", r.meta.solver);
  fmt::print(")\n");
}

/// The continuum's law when the case states none: the cached calibration of the case's grains
/// (rheology_cache.h) if there is one; says which law the FEM will use on rank 0.
void pick_continuum_law(Case& c, const std::vector<SolverEntry>& solvers, bool say) {
  const bool fem = std::any_of(solvers.begin(), solvers.end(),
                               [](const SolverEntry& s) { return s.name == "fem"; });
  if (!fem) return;
  const std::string note = use_cached_rheology(c);
  if (say && !note.empty()) {
    fmt::print("{}\n", note);
    std::fflush(stdout);  // before the solvers' progress lines on stderr
  }
}

/// After a run that a signal stopped: where its partial results are, how to go on; returns
/// the shell's code for that signal (128 + signal).
int report_interrupt(const RunArgs& a, const RunOptions& opt) {
  const int sig = interrupt_signal();
  if (!opt.writer) return 128 + sig;
  std::string how;
  if (std::filesystem::exists(opt.out_dir + "/dem.checkpoint")) {
    std::string sets;
    for (const auto& s : a.sets) sets += fmt::format(" --set '{}'", s);
    how = fmt::format("; go on with:\n  grainlift run {}{} --solver {} --resume {}", a.case_path,
                      sets, a.solver, opt.out_dir);
  }
  fmt::print(stderr, "grainlift: interrupted by signal {}: the results so far are in {}/ (marked "
             "partial in summary.json and the .h5 metadata){}\n", sig, opt.out_dir, how);
  return 128 + sig;
}

int cmd_run(const RunArgs& a) {
  Case c = load_case(a.case_path, a.sets);
  const auto solvers = pick_solvers(a.solver);
  pick_continuum_law(c, solvers, !a.quiet && process_rank() == 0);
  RunOptions opt;
  opt.out_dir = a.out.empty() ? default_out_dir(a.case_path) : a.out;
  if (!a.resume.empty()) {
    if (!a.out.empty() && std::filesystem::path(a.out) != std::filesystem::path(a.resume)) {
      throw InputError(fmt::format("--resume {} goes on in that folder: leave out --out {}",
                                   a.resume, a.out));
    }
    opt.out_dir = a.resume;
    opt.resume = true;
  }
  set_threads(opt, a.threads, a.replicas);
  // under mpirun every rank solves (the continuum is distributed), rank 0 alone reports and
  // writes the files
  opt.writer = process_rank() == 0;
  opt.progress = !a.quiet && opt.writer;
  install_interrupt_handlers();
  const auto results = run_solvers(c, solvers, opt);
  if (opt.writer) print_results(results, opt.out_dir);
  if (interrupt_signal()) return report_interrupt(a, opt);
  return exit_success;
}

int cmd_validate(const std::vector<std::string>& files, const std::vector<std::string>& sets) {
  int failures = 0;
  for (const auto& f : files) {
    try {
      if (is_rheology_file(f)) {
        const RheologyFile law = read_rheology_file(f);
        std::string extra;
        if (law.wall) extra += fmt::format(", wall friction {:.3g}", law.wall->friction);
        if (law.nonlocal)
          extra += fmt::format(", nonlocal A {:.3g} +- {:.2g}", law.nonlocal->amplitude,
                               law.nonlocal->amplitude_err);
        fmt::print("{}: ok (rheology file: mu_s {:.4g}, mu_2 {:.4g}, I0 {:.4g}, I in [{:.3g}, "
                   "{:.3g}]{})\n",
                   f, law.mu_i.mu_s, law.mu_i.mu_2, law.mu_i.I0, law.I_min, law.I_max, extra);
        continue;
      }
      load_case(f, sets);
      fmt::print("{}: ok\n", f);
    } catch (const InputError& e) {
      std::cerr << e.what();
      ++failures;
    }
  }
  return failures ? exit_bad_input : exit_success;
}

int cmd_compare(const std::string& a, const std::string& b, bool json) {
  const Comparison c = compare_results(read_result(a), read_result(b));
  if (json) fmt::print("{}\n", comparison_json(c, 2));
  else fmt::print("{}", comparison_text(c));
  return exit_success;
}

/// Splits "v1,v2,[1,2]" at top-level commas.
std::vector<std::string> split_values(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  int depth = 0;
  bool quoted = false;
  for (char ch : s) {
    if (ch == '"') quoted = !quoted;
    if (!quoted && (ch == '[' || ch == '{')) ++depth;
    if (!quoted && (ch == ']' || ch == '}')) --depth;
    if (ch == ',' && depth == 0 && !quoted) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += ch;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

std::string safe_name(std::string s) {
  for (char& ch : s)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '-' || ch == '_' ||
          ch == '='))
      ch = '_';
  return s;
}

int cmd_sweep(const RunArgs& a, const std::string& vary) {
  install_interrupt_handlers();
  if (process_count() > 1)
    throw InputError(fmt::format(
        "sweep runs on one MPI process only (started as one of {} ranks): run it without "
        "mpirun, or use mpirun with `grainlift run` for each member",
        process_count()));
  const auto eq = vary.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == vary.size())
    throw InputError(fmt::format("--vary '{}': expected section.key=v1,v2,...", vary));
  const std::string key = vary.substr(0, eq);
  const auto values = split_values(vary.substr(eq + 1));
  // Validate every member of the series before running any of them.
  std::vector<Case> cases;
  for (const auto& v : values) {
    auto sets = a.sets;
    sets.push_back(key + "=" + v);
    cases.push_back(load_case(a.case_path, sets));
  }
  const auto solvers = pick_solvers(a.solver);
  for (auto& c : cases) pick_continuum_law(c, solvers, !a.quiet && &c == &cases.front());
  const std::string out = a.out.empty() ? default_out_dir(a.case_path) + "-sweep" : a.out;
  make_directories(out);
  std::string csv =
      "key,value,solver,drag,drag_stderr,lift,lift_stderr,torque,torque_stderr,lift_over_drag,"
      "spin_ratio,contacts,wall_seconds,run_dir\n";
  auto num = [](const std::optional<double>& v) {
    return v && std::isfinite(*v) ? fmt::format("{:.10g}", *v) : std::string();
  };
  for (std::size_t i = 0; i < values.size(); ++i) {
    RunOptions opt;
    opt.out_dir = out + "/" + safe_name(key + "=" + values[i]);
    set_threads(opt, a.threads, a.replicas);
    opt.progress = !a.quiet;
    fmt::print("sweep {}/{}: {} = {}\n", i + 1, values.size(), key, values[i]);
    std::fflush(stdout);
    const auto results = run_solvers(cases[i], solvers, opt);
    for (const auto& r : results) {
      if (!r.means) continue;
      const auto& m = *r.means;
      csv += fmt::format("{},\"{}\",{},{},{},{},{},{},{},{},{},{},{},{}\n", key, values[i],
                         r.meta.solver, num(m.drag), num(m.drag_stderr), num(m.lift),
                         num(m.lift_stderr), num(m.torque), num(m.torque_stderr),
                         num(m.drag != 0 ? std::optional<double>(m.lift / m.drag) : std::nullopt),
                         num(cases[i].spin_ratio()), num(m.contacts), num(r.meta.wall_seconds),
                         opt.out_dir);
    }
    write_text_atomically(out + "/sweep.csv", csv);  // rewritten after each run
    if (interrupt_signal()) {
      fmt::print(stderr, "grainlift: sweep interrupted by signal {} at {} = {}: its results so "
                 "far in {}/ (partial), the table in {}/sweep.csv\n", interrupt_signal(), key,
                 values[i], opt.out_dir, out);
      return 128 + interrupt_signal();
    }
  }
  fmt::print("sweep table: {}/sweep.csv\n", out);
  return exit_success;
}

/// Prints @p text, the report of an exception that ended the command, and returns @p code.
/// Under mpirun, if every rank failed here together (bad input, which every rank reads, or a
/// solve that did not converge), rank 0 alone prints; if some ranks failed alone, this one
/// prints @p what with its rank and ends all ranks (failed_on_every_rank()).
int report_failure(const std::string& text, const std::string& what, int code) {
  if (process_count() > 1) failed_on_every_rank(what, code);  // returns only if all did
  if (process_rank() == 0) std::cerr << text;
  return code;
}

void add_run_options(CLI::App* cmd, RunArgs& a) {
  cmd->add_option("CASE", a.case_path, "case file (TOML), e.g. cases/demo/demo.toml")->required();
  cmd->add_option("--solver", a.solver, "which solver to run")
      ->check(CLI::IsMember({"dem", "fem", "both"}))
      ->capture_default_str();
  cmd->add_option("--out", a.out, "output folder (default: out/<case name>)");
  cmd->add_option("--set", a.sets,
                  "override a case key, section.key=value (TOML value; repeatable; validated "
                  "like the file)");
  cmd->add_option("--threads", a.threads,
                  "threads (two or more with both solvers: they run at once, the continuum on "
                  "one core, the DEM's team on the cores it leaves)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  cmd->add_option("--replicas", a.replicas,
                  "DEM: independent runs side by side (seeds dem.seed, dem.seed + 1, ...; one "
                  "bed each; the threads shared out), pooled with errors from their spread")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  cmd->add_flag("--quiet", a.quiet, "no progress lines");
}

/// `grainlift calibrate` and its options into @p cal.
CLI::App* add_calibrate_command(CLI::App& app, CalibrateArgs& cal) {
  auto* calibrate = app.add_subcommand(
      "calibrate", "measure mu(I) and Phi(I) of the case's grains in a DEM shear cell and fit "
                   "them: a rheology file for continuum.rheology_file");
  calibrate->add_option("CASE", cal.case_path, "case file whose grains are calibrated")->required();
  calibrate->add_option("--out", cal.out, "rheology file to write (default: rheology.toml beside "
                                          "the case)");
  calibrate->add_option("--set", cal.sets, "override a case key (as for run)");
  calibrate->add_option("--pressure", cal.pressure,
                        "P of the cell, Pa (default: the case's: lid + lithostatic, or "
                        "continuum.ambient_pressure)")
      ->check(CLI::PositiveNumber);
  calibrate->add_option("--inertial-numbers", cal.inertial_numbers,
                        "target inertial numbers (default 1e-3 3e-3 1e-2 3e-2 0.06 0.1 0.2 0.5)")
      ->check(CLI::Range(1e-5, 2.0));
  calibrate->add_option("--strain-scale", cal.strain_scale,
                        "multiplies each point's run-in and window strain (--nonlocal: travel)")
      ->check(CLI::Range(0.02, 100.0))
      ->capture_default_str();
  calibrate->add_option("--threads", cal.threads, "threads: the points (--nonlocal: seeds) at once")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  calibrate->add_flag("--quiet", cal.quiet, "no line per point");
  calibrate->add_option("--wall", cal.wall_runs,
                        "DEM results of the case (folders or dem.h5, with the slip histogram): "
                        "fit the grains' wall law into the file's [wall] table "
                        "(continuum.wall_law = \"measured\" or \"measured_slip\")");
  calibrate->add_flag("--nonlocal", cal.nonlocal,
                      "instead of the mu(I) sweep: fit the nonlocal fluidity's A on a creeping "
                      "layer (gravity under a sheared top) with the mu(I) of the existing "
                      "rheology file (--out), into its [nonlocal] table");
  calibrate->add_option("--seeds", cal.seeds,
                        "independent beds of the creeping-layer cell, pooled (--nonlocal)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  calibrate->add_option("--creep-inertial-number", cal.creep_inertial_number,
                        "nominal I of the creeping-layer cell's sheared top (--nonlocal): the lid "
                        "moves at 10 I sqrt(P / rho_s); lower it when the top slides on the lid")
      ->check(CLI::Range(1e-4, 1.0))
      ->capture_default_str();
  return calibrate;
}

/// The options of `grainlift export lammps` and `grainlift import lammps`.
struct LammpsArgs {
  std::string export_case, export_dir, import_dir, import_out;
  std::vector<std::string> export_sets;
};
/// The two LAMMPS subcommands (parsed when set).
struct LammpsCommands {
  CLI::App* exporter;
  CLI::App* importer;
};

/// `grainlift export lammps` and `grainlift import lammps` with their options into @p a.
LammpsCommands add_lammps_commands(CLI::App& app, LammpsArgs& a) {
  auto* exporter = app.add_subcommand("export", "write a case for another code");
  exporter->require_subcommand(1);
  auto* export_lammps = exporter->add_subcommand(
      "lammps", "the case's prepared bed and scene as a LAMMPS input script and data file in DIR "
                "(docs/lammps.md); run it with lmp or mpirun, then `grainlift import lammps`");
  export_lammps->add_option("CASE", a.export_case, "case file (TOML)")->required();
  export_lammps->add_option("DIR", a.export_dir, "folder to write in.grainlift and bed.data to")
      ->required();
  export_lammps->add_option("--set", a.export_sets, "override a case key (as for run)");

  auto* importer = app.add_subcommand("import", "read another code's run of an exported case");
  importer->require_subcommand(1);
  auto* import_lammps = importer->add_subcommand(
      "lammps", "LAMMPS's outputs in DIR (from `grainlift export lammps`) as OUT/dem.h5 and "
                "summary.json, through the DEM's post-processing");
  import_lammps->add_option("DIR", a.import_dir, "the exported folder LAMMPS ran in")->required();
  import_lammps->add_option("--out", a.import_out, "output folder (default: DIR/grainlift)");
  return {export_lammps, import_lammps};
}

/// `grainlift keys`: every case key with its type, unit, default and range (or the Markdown
/// table of docs/case-format.md).
int cmd_keys(bool markdown) {
  if (markdown) {
    fmt::print("{}", keys_markdown());
    return exit_success;
  }
  for (const auto& k : case_keys())
    fmt::print("{:32} {:16} {:10} default {:18} accepted {}\n", k.path, type_name(k.type), k.unit,
               k.required ? "(required)" : k.default_text, accepted_range(k));
  return exit_success;
}

/// `grainlift --version`: the version, the revision and the DEM's SIMD target.
std::string version_text() {
  std::string v = grainlift_version() + " (" + grainlift_git_revision() + ")";
#ifdef GRAINLIFT_HAVE_DEM
  v += "\nDEM SIMD: " + dem::simd_target() + " (this build and CPU: " + dem::simd_targets() +
       "; GRAINLIFT_SIMD chooses one)";
  if (const std::string why = dem::simd_setting_error(); !why.empty()) v += "\n" + why;
#endif
  return v;
}

}  // namespace

int main_with_args(int argc, char** argv) {
  CLI::App app{"grainlift: forces on a cylinder that translates and spins through a granular "
               "medium, by DEM and by a mu(I) continuum, from one case file.\n"
               "Exit codes: 0 success, 1 a run that failed, 2 bad input."};
  app.require_subcommand(1);
  app.set_version_flag("--version", version_text());

  RunArgs run_args;
  auto* run = app.add_subcommand("run", "run a case with one or both solvers");
  add_run_options(run, run_args);
  run->add_option("--resume", run_args.resume,
                  "DEM: go on from the checkpoint in this output folder (a run writes one every "
                  "dem.checkpoint_minutes and when Ctrl-C or SIGTERM stops it); the same case "
                  "file and --set options");

  std::vector<std::string> validate_files, validate_sets;
  auto* validate = app.add_subcommand("validate", "check case files without running them");
  validate->add_option("CASE", validate_files, "case files")->required();
  validate->add_option("--set", validate_sets, "overrides applied to every file");

  std::string cmp_a, cmp_b;
  bool cmp_json = false;
  auto* compare = app.add_subcommand(
      "compare", "differences of B against A: drag, lift, torque (relative) and sigma_n, sigma_t "
                 "(L2 and max, normalised by a pressure scale)");
  compare->add_option("A", cmp_a, "reference result file (.h5)")->required();
  compare->add_option("B", cmp_b, "result file to compare (.h5)")->required();
  compare->add_flag("--json", cmp_json, "print JSON");

  RunArgs sweep_args;
  std::string vary;
  auto* sweep = app.add_subcommand("sweep", "run a series varying one key; writes sweep.csv");
  add_run_options(sweep, sweep_args);
  sweep->add_option("--vary", vary, "section.key=v1,v2,... (any key)")->required();

  CalibrateArgs cal;
  auto* calibrate = add_calibrate_command(app, cal);

  std::string report_dir;
  auto* report = app.add_subcommand(
      "report", "one HTML page on a result folder: DIR/report.html with surface stresses, "
                "their split, fields and a table of both solvers (scripts/report.py)");
  report->add_option("DIR", report_dir, "result folder with dem.h5 and/or fem.h5")->required();

  LammpsArgs lammps;
  const LammpsCommands lammps_cmds = add_lammps_commands(app, lammps);

  bool markdown = false;
  auto* keys = app.add_subcommand("keys", "list every case key with unit, default and range");
  keys->add_flag("--markdown", markdown, "as the Markdown table of docs/case-format.md");
  auto* schema = app.add_subcommand("schema", "list every group, attribute and dataset of the "
                                              "result files with unit, shape and presence");
  schema->add_flag("--markdown", markdown, "as the Markdown table of docs/schema.md");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? exit_success : exit_bad_input;
  }

  try {
    if (*run) return cmd_run(run_args);
    if (*validate) return cmd_validate(validate_files, validate_sets);
    if (*compare) return cmd_compare(cmp_a, cmp_b, cmp_json);
    if (*sweep) return cmd_sweep(sweep_args, vary);
    if (*calibrate) return cmd_calibrate(cal);
    if (*report) return cmd_report(report_dir);
    if (*lammps_cmds.exporter) {
      return cmd_export_lammps(lammps.export_case, lammps.export_sets, lammps.export_dir);
    }
    if (*lammps_cmds.importer) {
      return cmd_import_lammps(lammps.import_dir, lammps.import_out.empty()
                                                      ? lammps.import_dir + "/grainlift"
                                                      : lammps.import_out);
    }
    if (*schema) return cmd_schema(markdown);
    if (*keys) return cmd_keys(markdown);
  } catch (const InputError& e) {
    std::string msg = e.what();
    if (!msg.empty() && msg.back() != '\n') msg += '\n';
    return report_failure("grainlift: bad input:\n" + msg, e.what(), exit_bad_input);
  } catch (const std::bad_alloc&) {
    return report_failure(
        "grainlift: run failed: out of memory (an allocation failed); the results of the "
        "solvers that had finished are in the --out folder; a smaller case (domain, grains, "
        "continuum.refinement) or a machine with more memory\n",
        "out of memory", exit_run_failed);
  } catch (const std::exception& e) {  // RunError and anything else
    return report_failure(std::string("grainlift: run failed: ") + e.what() + "\n", e.what(),
                          exit_run_failed);
  } catch (...) {
    return report_failure("grainlift: run failed: unknown exception\n", "unknown exception",
                          exit_run_failed);
  }
  return exit_success;
}

}  // namespace grainlift::app
