// Helpers shared by the CLI commands: argument parsing and JSON output.
#pragma once

#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/math/vec.h>
#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "registry.h"

namespace msh::cli {

// Parses "a,b,c,..." (spaces after numbers allowed) into numbers; throws UsageError naming `what` on an empty
// list, an empty item, a malformed or a non-finite number.
std::vector<double> parse_list(const std::string& text, const std::string& what);

// Splits "a,b,c" at the commas: "" gives no item, "a,,b" an empty middle one, a trailing comma none.
std::vector<std::string> split_list(const std::string& text);

// Parses "X,Y,Z" (spaces allowed) into a vector; throws UsageError naming `what` on malformed or
// non-finite input. Does not normalize.
Vec3d parse_vec3(const std::string& text, const std::string& what);

// Throws UsageError("<what> must be in [lo, hi], got <v>") unless lo <= v <= hi (NaN fails): io/error.h.
using ::msh::require_range;

// Caps TBB at `threads` workers while the result lives; threads <= 0: no cap (nullptr).
std::unique_ptr<tbb::global_control> thread_limit(int threads);

// The one --threads option of every command that runs in parallel: 0 = all cores, at most 1024; every
// output is bit-identical whatever the count (the project's rule), which the help says.
CLI::Option* add_threads_option(CLI::App* command, int& threads);

// The options every kind of command shares, declared once so that their names, help and checks agree:
// --quiet (long work reports progress on stderr unless it is given), --json (`what` is printed instead of
// the table), --out DIR (a command writing several files: the folder is created with its parents) and
// --out FILE with --format (a command writing one table: dds, ktx2, exr, npy or h; the format from the
// extension unless --format names it).
CLI::Option* add_quiet_flag(CLI::App* command, bool& quiet);
CLI::Option* add_json_flag(CLI::App* command, bool& json, const std::string& what = "Print one JSON object");
CLI::Option* add_out_dir_option(CLI::App* command, std::string& dir);
struct TableOutput {
  std::string out, format;
};
void add_table_output(CLI::App* command, TableOutput& t);

// The format of a TableOutput, checked before any work: UsageError for PNG (a table is not an image; `hint`
// is appended, e.g. where its figures come from) and for a parent directory that does not exist.
io::FileFormat table_output_format(const TableOutput& t, const std::string& hint = "");

// Creates the folder of an add_out_dir_option (and its parents); UsageError("<option>: cannot create
// directory '<dir>'") when it cannot. Returns the path.
std::filesystem::path make_out_dir(const std::string& dir, const std::string& option = "--out");

// UsageError("<option>: directory '<parent>' does not exist") when the parent directory of `file` is missing.
void require_parent_dir(const std::filesystem::path& file, const std::string& option);

// The progress report of a long command: "microshadow: <what>: NN%" on stderr when the work passes a tenth
// (10%, 20%, ..., 100%, always increasing; called with the fraction done, one call at a time: the bakers
// serialize it, but their workers may report out of order, so a tenth can be passed over); an empty function
// when quiet.
std::function<void(double)> progress_in_tenths(const std::string& what, bool quiet);

// Prints one JSON object on stdout, one line, with full double precision.
void print_json(const nlohmann::json& j);

// A subcommand of `parent` with its own options struct, created here: CLI11 parses into *args and the
// subcommand's callback is run(*args). Use: const auto [c, o] = add_command<Opts>(g.bake, "x", "help",
// run_x);
template <class Args, class Run>
std::pair<CLI::App*, std::shared_ptr<Args>> add_command(CLI::App* parent, const std::string& name,
                                                        const std::string& help, Run run) {
  auto args = std::make_shared<Args>();
  CLI::App* c = parent->add_subcommand(name, help);
  c->callback([args, run] { run(*args); });
  return {c, args};
}

// What the measuring commands (verify micro-shadowing-term, plot micro-shadowing-fit) compare beside the
// registry's closed forms (occlusion::micro_shadowing_closed_form_terms): the id of the generic ALU fit's
// two-stage form (per pixel + per light, micro_shadowing::generic_vndf_alu_two_stage), generic-vndf-alu's
// GLSL form flagged two_stage.
std::string two_stage_fit_id();

// A CLI11 validator that rejects NaN/Inf (CLI11's own number parsing accepts "nan").
extern const CLI::Validator Finite;

}  // namespace msh::cli
