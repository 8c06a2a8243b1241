// mps_lab: command-line front end of the testbed.
//   mps_lab run --method=mps scenes/dambreak.json [--out DIR] [--set key=value]... [--end-time T]
//               [--checkpoint-every N] [--load-setting] [--profile]
//   mps_lab resume DIR [--end-time T] [--checkpoint-every N] [--profile]
//   mps_lab compare scenes/dambreak.json [--methods mps,isph,dfsph] [--out runs/dambreak] [--load-setting]
//   mps_lab bench [scene] [--methods ...] [--spacings 0.025,0.0125,0.005,0.0025] [--threads 1,2]
//               [--steps N] [--warmup-steps N] [--start-time T] [--json FILE]
//   mps_lab methods [--parameters]
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "app/commands.hpp"
#include "core/base/error.hpp"
#include "lab/data_directory.hpp"

namespace {

// `mps_lab run`: its options into `run`.
CLI::App* add_run_command(CLI::App& app, mps_lab::app::RunCommand& run) {
  CLI::App* run_app =
      app.add_subcommand("run", "run one method on a scene; frames, series.csv and run.json in the output folder");
  run_app->add_option("scene", run.scene, "scene file (JSON), e.g. scenes/dambreak.json")->required();
  run_app->add_option("--method,-m", run.method,
                      "method name (default: the scene's \"method\"); see `mps_lab methods`");
  run_app->add_option("--out,-o", run.out, "output folder (default: the scene's output.directory)");
  run_app
      ->add_option("--set,-s", run.set,
                   "override a scene key, e.g. --set time.time_step=1e-4; key?=value only where nothing gave the key "
                   "(repeatable)")
      ->take_last()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  run_app->add_option("--end-time", run.end_time, "simulated end time in s (overrides time.end_time)");
  run_app->add_option("--checkpoint-every", run.checkpoint_every,
                      "write the full state to <out>/checkpoint.bin every N steps, for `mps_lab resume` "
                      "(overrides output.checkpoint_every_steps; 0: only when stopped by Ctrl-C/SIGTERM)");
  run_app
      ->add_option("--threads", run.threads,
                   "OpenMP threads of every step (default 0: one thread or all, whichever the last measurement found "
                   "faster; docs/performance.md)")
      ->check(CLI::NonNegativeNumber);
  run_app->add_flag("--load-setting", run.load_setting,
                    "take the method's setting for wall loads before the --set overrides (`mps_lab methods -p` lists "
                    "it; docs/validation.md, \"Each method's load setting\")");
  run_app->add_flag("--quiet,-q", run.quiet, "no progress line and no summary line");
  run_app->add_flag("--profile", run.profile,
                    "print where the time went at the end: seconds, share and ms per step of each phase "
                    "(also in run.json \"profile\" of every run)");
  return run_app;
}

// `mps_lab resume`: its options into `resume`.
CLI::App* add_resume_command(CLI::App& app, mps_lab::app::ResumeCommand& resume) {
  CLI::App* resume_app = app.add_subcommand(
      "resume",
      "continue a run from its folder's checkpoint.bin (interrupted, killed, or completed and extended "
      "with --end-time), writing into the same folder");
  resume_app->add_option("directory", resume.directory, "the run folder (holds run.json and checkpoint.bin)")
      ->required();
  resume_app->add_option("--end-time", resume.end_time, "simulated end time in s (default: the run's)");
  resume_app->add_option("--checkpoint-every", resume.checkpoint_every,
                         "checkpoint every N steps (default: as the run did)");
  resume_app
      ->add_option("--threads", resume.threads,
                   "OpenMP threads of every step (default 0: one thread or all, whichever the last measurement found "
                   "faster; docs/performance.md)")
      ->check(CLI::NonNegativeNumber);
  resume_app->add_flag("--quiet,-q", resume.quiet, "no progress line and no summary line");
  resume_app->add_flag("--profile", resume.profile, "print the per-phase profile of this session at the end");
  return resume_app;
}

// `mps_lab compare`: its options into `compare`.
CLI::App* add_compare_command(CLI::App& app, mps_lab::app::CompareCommand& compare) {
  CLI::App* compare_app =
      app.add_subcommand("compare", "run several methods on one scene, write summary.csv, figures and report.md");
  compare_app->add_option("scene", compare.scene, "scene file (JSON)")->required();
  compare_app->add_option("--methods", compare.methods, "comma-separated methods (default: all registered)")
      ->delimiter(',');
  compare_app->add_option("--out,-o", compare.out, "output folder (default: runs/<scene name>)");
  compare_app->add_option("--set,-s", compare.set, "override a scene key for every method (repeatable)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  compare_app->add_option("--end-time", compare.end_time, "simulated end time in s");
  compare_app->add_flag("--load-setting", compare.load_setting,
                        "each method with its setting for wall loads before the --set overrides (`mps_lab methods "
                        "-p`; docs/validation.md, \"Each method's load setting\")");
  compare_app->add_flag("!--no-analysis", compare.analysis, "skip the Python figures and report");
  compare_app->add_flag("--quiet,-q", compare.quiet, "no progress and no table");
  return compare_app;
}

// `mps_lab bench`: its options into `bench`.
CLI::App* add_bench_command(CLI::App& app, mps_lab::app::BenchCommand& bench) {
  CLI::App* bench_app = app.add_subcommand(
      "bench", "measure speed: kernels and whole steps of each method at several resolutions (docs/performance.md)");
  bench_app->add_option("scene", bench.scene, "scene file (default: scenes/dambreak.json)");
  bench_app->add_option("--methods", bench.methods, "comma-separated methods (default: all registered)")
      ->delimiter(',');
  bench_app
      ->add_option("--spacings", bench.spacings, "comma-separated particle spacings l0 in m (default: the scene's)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  bench_app->add_option("--threads", bench.threads, "comma-separated OpenMP thread counts (default: OMP_NUM_THREADS)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  bench_app
      ->add_option("--time-step-per-spacing", bench.time_step_per_spacing,
                   "time step = this x l0, s/m (default 0.02: the spec's 5e-4 s at l0 = 0.025; 0: the scene's)")
      ->check(CLI::NonNegativeNumber);
  bench_app->add_option("--start-time", bench.start_time, "run unmeasured to this simulated time first, s")
      ->check(CLI::NonNegativeNumber);
  bench_app->add_option("--warmup-steps", bench.warmup_steps, "unmeasured steps before the measured ones (default 5)")
      ->check(CLI::NonNegativeNumber);
  bench_app->add_option("--steps", bench.steps, "measured steps per case (default 20)")->check(CLI::PositiveNumber);
  bench_app->add_option("--set,-s", bench.set, "override a scene key (repeatable)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  bench_app
      ->add_option("--per-spacing", bench.per_spacing,
                   "KEY=FACTOR: set a scene key to FACTOR x l0 at every spacing, e.g. "
                   "methods.dfsph.max_time_step=1.0 (repeatable)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  bench_app->add_flag("!--no-kernels", bench.kernels, "skip the kernel micro-benchmarks");
  bench_app->add_option("--json", bench.json, "also write every measurement to this JSON file");
  bench_app->add_flag("--quiet,-q", bench.quiet, "no line per case on stderr");
  return bench_app;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"mps_lab: a testbed comparing incompressible particle methods (MPS, ISPH, DFSPH) on the same scenes"};
  app.require_subcommand(1);
  app.set_version_flag("--version", mps_lab::version_line());

  mps_lab::app::RunCommand run;
  CLI::App* run_app = add_run_command(app, run);
  mps_lab::app::ResumeCommand resume;
  CLI::App* resume_app = add_resume_command(app, resume);
  mps_lab::app::CompareCommand compare;
  CLI::App* compare_app = add_compare_command(app, compare);
  mps_lab::app::BenchCommand bench;
  CLI::App* bench_app = add_bench_command(app, bench);

  bool with_parameters = false;
  auto* methods_app = app.add_subcommand("methods", "list the registered methods, one line each");
  methods_app->add_flag("--parameters,-p", with_parameters, "also list every parameter, default and wall treatment");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  }

  try {
    if (app.got_subcommand(run_app)) return mps_lab::app::run_command(run);
    if (app.got_subcommand(resume_app)) return mps_lab::app::resume_command(resume);
    if (app.got_subcommand(compare_app)) return mps_lab::app::compare_command(compare);
    if (app.got_subcommand(bench_app)) return mps_lab::app::bench_command(bench, argv);
    if (app.got_subcommand(methods_app)) return mps_lab::app::methods_command(with_parameters);
  } catch (const mps_lab::InputError& error) {
    std::fprintf(stderr, "mps_lab: error: %s\n", error.what());
    return 2;
  } catch (const mps_lab::OutputError& error) {
    std::fprintf(stderr, "mps_lab: error: %s\n", error.what());
    return 3;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "mps_lab: internal error: %s\n", error.what());
    return 4;
  }
  return 0;
}
