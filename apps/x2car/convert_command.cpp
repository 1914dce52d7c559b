// x2car convert: turns an extrinsic between the forms users meet (io/extrinsic_formats.hpp).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <array>
#include <iostream>
#include <optional>
#include <sstream>

#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/output_paths.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/extrinsic_formats.hpp"
#include "x2car/io/extrinsic_merge.hpp"
#include "x2car/io/result_json.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::cli {
namespace {

struct ConvertArguments {
  std::vector<std::string> values;
  std::string input_path;
  std::string from = "auto";
  std::string to = "all";
  std::string parent_frame;
  std::string child_frame;
  bool invert = false;
  std::string output_path;
  std::string merge_into_path;
  std::string prior_path;
  std::string prior_from = "auto";
};

constexpr const char* kSourceOnCommandLine = "the command line";
// --from's name for a result JSON of `calibrate` (an input form only; auto recognises it).
constexpr const char* kResultForm = "result";

std::string read_source_text(const ConvertArguments& arguments) {
  if (!arguments.values.empty() && !arguments.input_path.empty()) {
    throw std::invalid_argument("give the extrinsic either as VALUES or with --input, not both");
  }
  if (!arguments.values.empty()) {
    std::string text;
    for (const auto& value : arguments.values) text += value + " ";
    return text;
  }
  if (arguments.input_path.empty()) {
    throw std::invalid_argument(
        "no extrinsic given: pass VALUES (e.g. 1.2 0 1.8 0.5 -1 2) or --input FILE ('-' reads "
        "stdin)");
  }
  if (arguments.input_path == "-") {
    std::ostringstream buffer;
    buffer << std::cin.rdbuf();
    return buffer.str();
  }
  return io::read_text_file(arguments.input_path);
}

io::ExtrinsicFormat resolve_input_format(const std::string& from, const std::string& text,
                                         const std::string& source_name) {
  if (from != "auto") return io::extrinsic_format_from_string(from);
  if (const auto detected = io::detect_extrinsic_format(text)) return *detected;
  const std::size_t numbers = io::split_number_tokens(text).size();
  if (numbers == 6) {
    throw InputError(source_name,
                     "six numbers could be x y z roll pitch yaw in degrees or in radians: say "
                     "--from xyzrpy-deg or --from xyzrpy-rad");
  }
  throw InputError(source_name,
                   fmt::format("cannot tell the form of this extrinsic ({} numbers); name it with "
                               "--from (one of: {})",
                               numbers, io::join(io::extrinsic_format_names())));
}

Extrinsic parse_input(const std::string& text, io::ExtrinsicFormat format,
                      const ConvertArguments& arguments, const std::string& source_name) {
  // In files that may hold several sensors, --child picks one; elsewhere it names the frame.
  const std::optional<std::string> child =
      arguments.child_frame.empty() ? std::nullopt : std::optional(arguments.child_frame);
  Extrinsic extrinsic;
  if (format == io::ExtrinsicFormat::kUrdf) {
    extrinsic = io::parse_urdf(text, source_name, child);
  } else if (format == io::ExtrinsicFormat::kAutoware) {
    extrinsic = io::parse_autoware(text, source_name, child);
  } else {
    extrinsic = io::parse_extrinsic(text, format, source_name);
  }
  if (child) extrinsic.child_frame = *child;
  if (!arguments.parent_frame.empty()) extrinsic.parent_frame = arguments.parent_frame;
  return extrinsic;
}

std::string indented(const std::string& text) {
  std::string result;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) result += "  " + line + "\n";
  return result;
}

std::string render_output(const Extrinsic& extrinsic, const std::string& to) {
  if (to != "all") return io::format_extrinsic(extrinsic, io::extrinsic_format_from_string(to));
  std::string text = fmt::format("{} from {}:\n", extrinsic.parent_frame, extrinsic.child_frame);
  for (const auto& name : io::extrinsic_format_names()) {
    const auto format = io::extrinsic_format_from_string(name);
    text += fmt::format("\n{}:\n{}", name, indented(io::format_extrinsic(extrinsic, format)));
  }
  return text;
}

void write_or_print(const std::string& output, const std::string& path) {
  if (path.empty()) {
    std::cout << output;
    if (!output.empty() && output.back() != '\n') std::cout << '\n';
  } else {
    io::write_text_file(path, output);
  }
}

// --merge-into: the results' estimated angles written into the user's Autoware YAML or URDF,
// everything else of that file kept (io/extrinsic_merge.hpp); the file itself is never changed.
int run_merge(const ConvertArguments& arguments, const std::string& text,
              const std::string& source_name) {
  if (!io::looks_like_result_json(text)) {
    throw InputError(source_name, "--merge-into takes a result JSON of calibrate as --input");
  }
  if (arguments.invert || arguments.to != "all") {
    throw std::invalid_argument("--merge-into writes the file's own form: no --to or --invert");
  }
  const std::array<NamedPath, 1> outputs = {{{"--out", arguments.output_path}}};
  const std::array<NamedPath, 2> inputs = {
      {{"--input", arguments.input_path}, {"--merge-into", arguments.merge_into_path}}};
  check_output_files(outputs, inputs);
  const std::string target = io::read_text_file(arguments.merge_into_path);
  const std::optional<io::ExtrinsicFormat> form = io::detect_extrinsic_format(target);
  if (form != io::ExtrinsicFormat::kAutoware && form != io::ExtrinsicFormat::kUrdf) {
    throw InputError(arguments.merge_into_path,
                     "is neither an Autoware calibration YAML nor a URDF: nothing to merge into");
  }
  const std::vector<io::NamedResult> results = io::parse_named_results(text, source_name);
  // One sensor: --child names its entry in the file. Several: --child picks one; without it
  // every sensor with an ok result merges into the entry of its own name.
  std::vector<io::MergeRequest> requests;
  for (const io::NamedResult& named : results) {
    const bool single = results.size() == 1;
    if (!single && !arguments.child_frame.empty() && named.name != arguments.child_frame) continue;
    if (!named.result.ok()) {
      spdlog::warn("{}: {} ({}); not merged", named.name, to_string(named.result.status),
                   named.result.reason);
      continue;
    }
    const std::string child =
        single && !arguments.child_frame.empty() ? arguments.child_frame : named.name;
    requests.push_back({child, &named.result});
  }
  if (requests.empty()) {
    throw InputError(source_name,
                     "holds no ok result to merge" +
                         (arguments.child_frame.empty() ? std::string()
                                                        : " for --child " + arguments.child_frame));
  }
  const std::string vehicle_frame =
      arguments.parent_frame.empty() ? std::string("base_link") : arguments.parent_frame;
  const io::MergeOutcome merged =
      form == io::ExtrinsicFormat::kAutoware
          ? io::merge_into_autoware(target, arguments.merge_into_path, vehicle_frame, requests)
          : io::merge_into_urdf(target, arguments.merge_into_path, vehicle_frame, requests);
  std::cerr << "before -> after (" << arguments.merge_into_path << "):\n"
            << io::format_merge_table(merged);
  write_or_print(merged.text, arguments.output_path);
  return kExitOk;
}

// --prior: the result's estimated angles on a prior mounting in any form (its translation and
// other angles kept), written in the --to form.
int run_with_prior(const ConvertArguments& arguments, const std::string& text,
                   const std::string& source_name) {
  if (!io::looks_like_result_json(text)) {
    throw InputError(source_name, "--prior takes a result JSON of calibrate as --input");
  }
  const std::string prior_text = io::read_text_file(arguments.prior_path);
  const io::ExtrinsicFormat form =
      resolve_input_format(arguments.prior_from, prior_text, arguments.prior_path);
  ConvertArguments prior_arguments = arguments;
  prior_arguments.parent_frame.clear();
  const Extrinsic prior = parse_input(prior_text, form, prior_arguments, arguments.prior_path);
  const std::vector<io::NamedResult> results = io::parse_named_results(text, source_name);
  const io::NamedResult* chosen = nullptr;
  for (const io::NamedResult& named : results) {
    if (results.size() == 1 || named.name == arguments.child_frame) chosen = &named;
  }
  if (chosen == nullptr) {
    throw InputError(source_name, "holds the results of several sensors: pick one with --child");
  }
  if (!chosen->result.ok()) {
    throw InputError(source_name,
                     fmt::format("the result of {} is {}: nothing to merge ({})", chosen->name,
                                 to_string(chosen->result.status), chosen->result.reason));
  }
  const std::string vehicle_frame =
      arguments.parent_frame.empty() ? std::string("base_link") : arguments.parent_frame;
  io::MergeOutcome table;
  table.entries.emplace_back();
  Extrinsic merged = io::merge_into_extrinsic(prior, arguments.prior_path, vehicle_frame,
                                              chosen->result, &table.entries.back());
  if (arguments.invert) merged = inverse(merged);
  std::cerr << "before -> after (" << arguments.prior_path << "):\n"
            << io::format_merge_table(table);
  write_or_print(render_output(merged, arguments.to), arguments.output_path);
  return kExitOk;
}

int run_convert(const ConvertArguments& arguments) {
  const std::string source_name =
      arguments.input_path.empty() ? kSourceOnCommandLine : arguments.input_path;
  const std::string text = read_source_text(arguments);
  if (!arguments.merge_into_path.empty() && !arguments.prior_path.empty()) {
    throw std::invalid_argument("give --merge-into or --prior, not both");
  }
  if (!arguments.merge_into_path.empty()) return run_merge(arguments, text, source_name);
  if (!arguments.prior_path.empty()) return run_with_prior(arguments, text, source_name);
  Extrinsic extrinsic;
  if (arguments.from == kResultForm ||
      (arguments.from == "auto" && io::looks_like_result_json(text))) {
    // A result of `calibrate`: --child picks the sensor of a `calibrate all` file.
    const std::optional<std::string> sensor =
        arguments.child_frame.empty() ? std::nullopt : std::optional(arguments.child_frame);
    extrinsic = io::extrinsic_from_result_json(text, source_name, sensor);
    if (!arguments.parent_frame.empty()) extrinsic.parent_frame = arguments.parent_frame;
  } else {
    const io::ExtrinsicFormat format = resolve_input_format(arguments.from, text, source_name);
    extrinsic = parse_input(text, format, arguments, source_name);
  }
  if (arguments.invert) extrinsic = inverse(extrinsic);
  write_or_print(render_output(extrinsic, arguments.to), arguments.output_path);
  return kExitOk;
}

}  // namespace

RunCommand setup_convert_command(CLI::App& command) {
  auto arguments = std::make_shared<ConvertArguments>();
  std::vector<std::string> format_names = io::extrinsic_format_names();
  std::vector<std::string> from_names = format_names;
  from_names.insert(from_names.begin(), "auto");
  from_names.emplace_back(kResultForm);
  std::vector<std::string> to_names = format_names;
  to_names.insert(to_names.begin(), "all");

  command
      .add_option("values", arguments->values,
                  "The extrinsic as numbers on the command line, e.g. 1.2 0 1.8 0.5 -1 2")
      ->type_name("NUMBER");
  command
      .add_option("-i,--input", arguments->input_path, "Read the extrinsic from FILE ('-': stdin)")
      ->type_name("FILE");
  command
      .add_option("--from", arguments->from,
                  "Form of the input; auto recognises all but xyzrpy (result: a JSON of calibrate, "
                  "one sensor or all)")
      ->type_name("FORM")
      ->check(CLI::IsMember(from_names))
      ->capture_default_str();
  command.add_option("--to", arguments->to, "Form of the output; all prints every form")
      ->type_name("FORM")
      ->check(CLI::IsMember(to_names))
      ->capture_default_str();
  command.add_option("--parent", arguments->parent_frame, "Parent frame name (default base_link)")
      ->type_name("NAME");
  command
      .add_option("--child", arguments->child_frame,
                  "Child frame name; picks the sensor in URDF/YAML files that hold several")
      ->type_name("NAME");
  command.add_flag("--invert", arguments->invert, "Write child_from_parent instead");
  command.add_option("-o,--out", arguments->output_path, "Write to FILE instead of stdout")
      ->type_name("FILE");
  command
      .add_option("--merge-into", arguments->merge_into_path,
                  "Write the result JSON's estimated angles into this Autoware YAML or URDF, "
                  "keeping every other value (translations, unobserved angles, other sensors); "
                  "the merged file goes to --out or stdout, the before -> after table to stderr")
      ->type_name("FILE");
  command
      .add_option("--prior", arguments->prior_path,
                  "A prior mounting in any form (--child picks its entry): the result JSON's "
                  "estimated angles on it, its translation and other angles kept, written as --to")
      ->type_name("FILE");
  command.add_option("--prior-from", arguments->prior_from, "Form of --prior (as --from)")
      ->type_name("FORM")
      ->check(CLI::IsMember(from_names))
      ->capture_default_str();
  command.footer(
      "The extrinsic is parent_from_child (e.g. base_link from lidar), angles as in\n"
      "docs/conventions.md. Forms:\n"
      "  xyzrpy-deg, xyzrpy-rad  'x y z roll pitch yaw' in metres and degrees or radians\n"
      "  matrix                  4x4 homogeneous matrix, row-major\n"
      "  quaternion              'x y z qx qy qz qw' (TUM order)\n"
      "  urdf                    <joint> snippet with <origin xyz rpy>\n"
      "  autoware                sensor_kit_calibration.yaml style (metres, radians)\n"
      "  reference               the reference tool's 'Extrinsic:' matrix text\n"
      "\n"
      "Examples:\n"
      "  x2car convert --from xyzrpy-deg 1.2 0 1.8 0.5 -1 2 --to matrix\n"
      "  x2car convert --input extrinsic.txt --to autoware --child lidar_top\n"
      "  x2car convert --input lidar.json --merge-into sensor_kit_calibration.yaml \\\n"
      "      --child velodyne_top_base_link --out merged.yaml\n"
      "  x2car convert --input radar.json --prior measured.txt --prior-from xyzrpy-deg \\\n"
      "      --to autoware --child radar_front");
  return [arguments] { return run_convert(*arguments); };
}

}  // namespace x2car::cli
