// x2car convert: turns an extrinsic between the forms users meet (io/extrinsic_formats.hpp).
#include <fmt/format.h>

#include <iostream>
#include <optional>
#include <sstream>

#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/extrinsic_formats.hpp"
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

int run_convert(const ConvertArguments& arguments) {
  const std::string source_name =
      arguments.input_path.empty() ? kSourceOnCommandLine : arguments.input_path;
  const std::string text = read_source_text(arguments);
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
  const std::string output = render_output(extrinsic, arguments.to);
  if (arguments.output_path.empty()) {
    std::cout << output;
    if (!output.empty() && output.back() != '\n') std::cout << '\n';
  } else {
    io::write_text_file(arguments.output_path, output);
  }
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
      "  x2car convert --input extrinsic.txt --to autoware --child lidar_top");
  return [arguments] { return run_convert(*arguments); };
}

}  // namespace x2car::cli
