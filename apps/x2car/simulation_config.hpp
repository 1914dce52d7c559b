// `x2car simulate --config FILE`: a YAML file that sets the simulator's parameters (the fields of
// sim::SimulationOptions below the drive's identity, which stays on the command line: scenario,
// duration, seed, sensors, mountings, output formats). docs/simulator.md lists every key.
//
//   ins:
//     heading_sigma_deg: 0.1      # sections are the options structs; keys their fields
//   lidar:
//     beams: 32
//   route:
//     urban:
//       turn_probability: 0.8
//
// Keys are the fields' names; an angle's key ends in `_deg` and is given in degrees (the struct
// holds radians). A key the file leaves out keeps the value it had. YAML parsing lives here, at the
// front end, so that the library never reads files (STYLE.md).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/sim/simulation.hpp"

namespace x2car::cli {

// Applies the file's keys to `options`, then checks the options it can set. InputError naming the
// file, the line and the key ("lidar.beams") for: invalid YAML, an unknown key, a section that is
// not a mapping, a value of the wrong type (a number, an integer, true/false, a distortion model,
// a list of numbers), and values that the options' Check() rejects (then without a line).
void apply_simulation_config(const std::filesystem::path& path, sim::SimulationOptions& options);
void apply_simulation_config_text(std::string_view text, const std::string& source_name,
                                  sim::SimulationOptions& options);

// Every key with its value in `options`, as a config file that reads back to them; each line's
// comment gives the unit and meaning (`x2car simulate --print-config`).
std::string format_simulation_config(const sim::SimulationOptions& options);

// Every key, dotted ("route.urban.turn_probability"), in the order of the file.
std::vector<std::string> simulation_config_keys();

}  // namespace x2car::cli
