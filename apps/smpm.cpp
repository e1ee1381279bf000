// smpm: runs MPM simulations described by TOML input files and inspects their output.
//
//   smpm run input.toml [--set section.key=value ...] [-o out.h5] [--quiet]
//   smpm run --restart out.h5 [-o other.h5]
//   smpm info out.h5
//   smpm stability input.toml [--order 1,2,4] [--blend-alpha 0.8] [--blend-every 1,2]
//                             [--periodic-cx 2] [--method spectral]
//   smpm spectrum input.toml [--order ...] [--blend-alpha ...] [--blend-every ...] [--courant C]
//
// Threads: SMPM_THREADS=n (a positive integer), else OMP_NUM_THREADS, else every core; the
// results are the same bit for bit for any number. Waiting threads sleep (OMP_WAIT_POLICY=passive)
// unless OMP_WAIT_POLICY says otherwise.
//
// Exit status: 0 success, 2 bad input (nothing that looks like a run is written),
// 3 numerical failure (frames written so far are kept in the partial file), 130 / 143 for
// SIGINT / SIGTERM, 1 any other error (a full disk, a closed standard output).

#include "info_command.hpp"
#include "notes.hpp"
#include "progress.hpp"
#include "stability_command.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/output.hpp>
#include <sparsempm/run.hpp>
#include <sparsempm/threads.hpp>
#include <sparsempm/version.hpp>

#include <CLI/CLI.hpp>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <dlfcn.h>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace {

// The signal that asked the run to stop (SIGINT, SIGTERM), 0 while none has.
std::atomic<int> g_signal{0};
extern "C" void on_signal(int s) {
  g_signal.store(s);
}

int run_command(const std::string& input, const std::vector<std::string>& sets,
                const std::string& output, const std::string& restart, bool quiet) {
  using namespace smpm;
  using app::print_notes;
  RunOptions options;
  RunConfig cfg;
  if (!restart.empty()) {
    if (!input.empty() || !sets.empty())
      throw InputError("--restart takes the input and overrides stored in " + restart +
                       "; do not give an input file or --set");
    cfg = stored_config(restart);
    options.restart_from = restart;
  } else {
    if (input.empty())
      throw InputError("smpm run: give an input file (or --restart out.h5)");
    cfg = read_input_file(input, sets);
    print_notes(cfg);
  }
  options.output = output;
  options.interrupt = &g_signal;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  app::Progress bar(stderr, isatty(fileno(stderr)) != 0);
  double start_time = 0;
  bool first = true;
  RunReport r;
  try {
    r = run(cfg, options, [&](const Model& m, double end) {
      if (first) {
        start_time = restart.empty() ? 0.0 : m.time - 1e-300;
        first = false;
      }
      if (!quiet)
        bar.update(m.step, m.time, start_time, end);
    });
  } catch (...) {
    if (!quiet && !first)
      bar.finish();
    throw;
  }
  if (!quiet) {
    bar.finish();
    // A change relative to a zero start has no meaning: then none is printed.
    char change[32] = "";
    if (r.energy_start != 0)
      std::snprintf(change, sizeof change, " (%+.4f%%)",
                    100 * (r.energy_end - r.energy_start) / std::abs(r.energy_start));
    std::printf("completed %ld steps in %.3f s (%.0f steps/s); total energy %.6g -> %.6g%s; %d "
                "frames in %s (ParaView: %s)\n",
                r.steps, r.wall_seconds, r.wall_seconds > 0 ? r.steps / r.wall_seconds : 0.0,
                r.energy_start, r.energy_end, change, r.frames, r.output.c_str(),
                xdmf_path(r.output).c_str());
  }
  return 0;
}

struct RunArgs {
  std::string input, output, restart;
  std::vector<std::string> sets;
  bool quiet = false;
};

CLI::App* add_run(CLI::App& app, RunArgs& a) {
  CLI::App* run = app.add_subcommand("run", "run a simulation from a TOML input file");
  run->add_option("input", a.input, "input file (TOML)");
  run->add_option("--set", a.sets, "override an input entry, e.g. --set time.courant=0.3")
      ->allow_extra_args(false);
  run->add_option("-o,--output", a.output, "output HDF5 file (default: output.file of the input)");
  run->add_option("--restart", a.restart, "continue the run stored in this HDF5 file");
  run->add_flag("-q,--quiet", a.quiet, "no progress and no summary");
  return run;
}

// The options renamed for one vocabulary (README, "One vocabulary"): each earlier spelling is
// accepted in this release, hidden from --help, with a note when used.
class Aliases {
public:
  template <class T>
  void add(CLI::App* app, const std::string& earlier, const std::string& current, T& target) {
    CLI::Option* o = app->add_option(earlier, target)->group("");
    if constexpr (CLI::detail::type_count<T>::value != 1 ||
                  CLI::detail::expected_count<T>::value != 1)
      o->delimiter(',');
    list_.push_back({app, earlier, current});
  }
  void print_notes() const {
    for (const Alias& a : list_)
      if (a.app->parsed() && a.app->count(a.earlier) > 0)
        std::fprintf(stderr,
                     "smpm: note: %s is now %s (the earlier name is accepted in this "
                     "release only)\n",
                     a.earlier.c_str(), a.current.c_str());
  }

private:
  struct Alias {
    CLI::App* app;
    std::string earlier, current;
  };
  std::vector<Alias> list_;
};

CLI::App* add_stability(CLI::App& app, smpm::app::StabilityArgs& st, Aliases& aliases) {
  CLI::App* stab = app.add_subcommand(
      "stability", "critical Courant numbers of FLIP and FMPM(k) (FMPM 2026 Fig. 12)");
  stab->add_option("input", st.input, "input file (TOML)")->required();
  stab->add_option("--set", st.sets, "override an input entry")->allow_extra_args(false);
  stab->add_option("--order", st.orders, "FMPM orders k")->delimiter(',')->capture_default_str();
  stab->add_option("--blend-alpha", st.blend_alphas,
                   "blending fractions alpha of the blended rows (none: no blended rows)")
      ->delimiter(',')
      ->capture_default_str();
  stab->add_option("--blend-every", st.blend_every, "blend every m-th pass, for every alpha")
      ->delimiter(',')
      ->capture_default_str();
  stab->add_option("--periodic-cx", st.periodic_cx, "periodic FMPM budgets C_X (none: no rows)")
      ->delimiter(',')
      ->capture_default_str();
  stab->add_option("--method", st.method, "spectral | simulation | both")->capture_default_str();
  stab->add_option("--shifts", st.shifts, "lattice shifts in the spectral sweep")
      ->capture_default_str();
  stab->add_option("--frames", st.frames, "also sweep the frames of this run file");
  stab->add_option("--frame-stride", st.frame_stride, "use every n-th frame")
      ->capture_default_str();
  stab->add_option("-o,--output", st.output, "CSV table")->capture_default_str();
  stab->add_flag("-q,--quiet", st.quiet, "no progress lines");
  stab->add_flag("!--no-exact", st.exact, "leave out the exact consistent-mass row");
  stab->add_option("--position-alpha", st.position_alpha,
                   "alpha of the position update (FMPM 2026 Eqs. 8-9) for every row");
  stab->add_option("--max-energy-change", st.max_energy_change,
                   "simulation: also fail a run whose total energy changes by more than this "
                   "fraction");
  aliases.add(stab, "--k", "--order", st.orders);
  aliases.add(stab, "--blend", "--blend-alpha and --blend-every", st.blends);
  aliases.add(stab, "--periodic", "--periodic-cx", st.periodic_cx);
  return stab;
}

CLI::App* add_spectrum(CLI::App& app, smpm::app::SpectrumArgs& sp, Aliases& aliases) {
  CLI::App* spec = app.add_subcommand(
      "spectrum", "rho(A), cond(m~) and the truncation error of FMPM(k) against m~^-1");
  spec->add_option("input", sp.input, "input file (TOML)")->required();
  spec->add_option("--set", sp.sets, "override an input entry")->allow_extra_args(false);
  spec->add_option("--order", sp.orders, "FMPM orders k")->delimiter(',')->capture_default_str();
  spec->add_option("--blend-alpha", sp.blend_alphas, "blending fractions alpha")
      ->delimiter(',')
      ->capture_default_str();
  spec->add_option("--blend-every", sp.blend_every, "blend every m-th pass")
      ->delimiter(',')
      ->capture_default_str();
  spec->add_option("--courant", sp.courant, "also rho(T(C)) at this Courant number");
  spec->add_option("-o,--output", sp.output, "CSV table")->capture_default_str();
  aliases.add(spec, "--k", "--order", sp.orders);
  aliases.add(spec, "--alpha", "--blend-alpha", sp.blend_alphas);
  aliases.add(spec, "--every", "--blend-every", sp.blend_every);
  return spec;
}

// libgomp reads OMP_WAIT_POLICY once, when it is loaded, before main. Its default lets the
// threads that wait at the end of a parallel region spin; with another busy process on the same
// cores (two runs of a parameter study, ctest -j2) the spinning threads take the cores from the
// working ones: tests/cli/test_shock.py (15 runs of the shock, two at a time, two threads each)
// took 187 s with spinning and 38 s with passive waiting on two cores. So, unless the user chose
// a policy, the program starts itself once more with passive waiting; if that fails it goes on
// with libgomp's default. Only when /proc/self/exe is this program's own file: started through
// the dynamic loader (ld.so ./smpm …) or an emulator it is not, and the program goes on as it is.
void wait_passively_unless_chosen(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY"))
    return;
  Dl_info self{};
  struct stat program {
  }, exe{};
  if (!dladdr(reinterpret_cast<void*>(&wait_passively_unless_chosen), &self) || !self.dli_fname ||
      stat(self.dli_fname, &program) != 0 || stat("/proc/self/exe", &exe) != 0 ||
      program.st_dev != exe.st_dev || program.st_ino != exe.st_ino)
    return;
  if (setenv("OMP_WAIT_POLICY", "passive", 1) == 0)
    execv("/proc/self/exe", argv);
}

} // namespace

int main(int argc, char** argv) {
  wait_passively_unless_chosen(argv);
  CLI::App app{"sparsempm: the Material Point Method with explicit sparse operators"};
  app.set_version_flag("--version", std::string(smpm::kVersion));
  app.require_subcommand(1);
  RunArgs ra;
  smpm::app::StabilityArgs st;
  smpm::app::SpectrumArgs sp;
  std::string info_path;
  CLI::App* run = add_run(app, ra);
  Aliases aliases;
  CLI::App* stab = add_stability(app, st, aliases);
  CLI::App* spec = add_spectrum(app, sp, aliases);
  bool layout = false;
  CLI::App* info = app.add_subcommand("info", "describe a run's HDF5 output");
  info->add_option("file", info_path, "HDF5 file written by smpm run");
  info->add_flag("--layout", layout, "print the layout of every run file instead");
  // A first argument that names no command (CLI11 says only "A subcommand is required").
  const auto named = [&](const CLI::App* c) { return c->get_name() == argv[1]; };
  if (argc > 1 && argv[1][0] != '-' && app.get_subcommands(named).empty()) {
    std::fprintf(stderr,
                 "smpm: error: unknown command '%s' (expected run, stability, spectrum or "
                 "info; smpm --help lists them)\n",
                 smpm::clip(argv[1]).c_str());
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  aliases.print_notes();
  int code = 0;
  try {
    smpm::threads_from_environment(); // SMPM_THREADS, else OMP_NUM_THREADS or every core
    if (*run)
      code = run_command(ra.input, ra.sets, ra.output, ra.restart, ra.quiet);
    else if (*stab) {
      st.position_alpha_given = stab->count("--position-alpha") > 0; // a NaN given is refused
      code = smpm::app::stability_command(st);
    } else if (*spec)
      code = smpm::app::spectrum_command(sp);
    else
      code = smpm::app::info_command(info_path, layout);
  } catch (const smpm::InputError& e) {
    std::fprintf(stderr, "smpm: error: %s\n", e.what());
    code = 2;
  } catch (const smpm::Interrupted& e) {
    std::fprintf(stderr, "smpm: %s\n", e.what());
    code = 128 + e.signal(); // 130 for SIGINT, 143 for SIGTERM
  } catch (const smpm::NumericalError& e) {
    std::fprintf(stderr, "smpm: numerical failure: %s\n", e.what());
    code = 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "smpm: error: %s\n", e.what());
    code = 1;
  }
  // What was printed must have reached standard output (a closed pipe or a full disk).
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::fprintf(stderr, "smpm: error: cannot write to standard output\n");
    return code == 0 ? 1 : code;
  }
  return code;
}
