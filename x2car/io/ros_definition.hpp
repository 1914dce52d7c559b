// Messages read by their definition (the .msg text a bag stores beside each topic: the root type's
// fields, then each type it uses after a `MSG: package/Type` line), for types whose layout varies
// between driver versions, such as NovAtel's INSPVA (issue 17: "where the message definition is in
// the bag"). Understood: the primitives (bool, byte, char, int8 ... uint64, float32, float64,
// string, ROS 1 time and duration), nested types (a bare name is of the containing type's package;
// `Header` is std_msgs/Header), fixed, bounded and variable arrays, bounded strings, constants and
// ROS 2 default values (both skipped), comments.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/io/ros_message.hpp"

namespace x2car::io {

class RosDefinition {
 public:
  // InputError naming `source` for a type the text uses but does not define, or a line that is
  // not a field, constant or comment.
  RosDefinition(std::string_view root_type, std::string_view text, const std::string& source);

  // The numeric leaves named in `paths` ("latitude", "header.stamp.sec", "nov_header.gps_week_
  // number"; ROS 1 times as "stamp.sec" and "stamp.nsec") of one message, as doubles; a path the
  // definition does not have is absent from the result. InputError when the message ends early.
  std::map<std::string, double> read_numbers(std::string_view bytes, RosEncoding encoding,
                                             const std::string& source,
                                             const std::vector<std::string>& paths) const;

 private:
  struct Field {
    std::string type;  // a primitive's name or a complex type's "package/Type"
    std::string name;
    bool is_array = false;
    int fixed_length = -1;  // -1: variable (or bounded) length
  };
  void walk(const std::string& type, const std::string& prefix, RosMessageReader& message,
            const std::vector<std::string>& paths, std::map<std::string, double>& out,
            int depth) const;

  std::string root_;
  std::map<std::string, std::vector<Field>> types_;
};

}  // namespace x2car::io
