// A simulated drive as a ROS 1 bag written by the ROS library itself (rosbag_storage, Debian's
// librosbag-dev): /odom, nav_msgs/Odometry from DRIVE_DIR/ins/ins.csv (time,x,y,z,vx,vy,vz,roll,
// pitch,yaw; radians), converted as write_odometry_mcap.mjs converts it (the pose is the device's
// in ENU, its orientation Rz(yaw) Ry(pitch) Rx(roll); the twist its velocity in its own axes,
// R^T v; frame "map", child frame "ins"), and /points, sensor_msgs/PointCloud2 from the binary PCD
// files of DRIVE_DIR/lidar (sorted by name; x2car's point layout: x y z intensity FLOAT32, ring
// UINT16, t FLOAT32, 22 bytes, the PCD's bytes as they are; the stamp from the file name's digits,
// 000012.300000.pcd: 12 s 300000000 ns). Messages in time order, each at its header stamp (a stamp
// of 0 at ros::TIME_MIN, 1 ns: a bag cannot hold time 0). --truncate cuts the closed file to 60 %
// of its size: a recording that did not close. C++17: ROS 1's message headers do not compile as
// C++20 (std::allocator<void>::rebind).
//   write_ros1_bag DRIVE_DIR OUT.bag [--compression none|lz4|bz2] [--truncate]
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/PointField.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot be read");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  for (std::string field; std::getline(stream, field, separator);) fields.push_back(field);
  return fields;
}

// The GNSS/INS log as Odometry messages; the stamp as ROS keeps it (whole seconds, nanoseconds).
std::vector<nav_msgs::Odometry> read_ins(const fs::path& csv) {
  std::stringstream text(read_file(csv));
  std::string line;
  std::getline(text, line);
  const std::vector<std::string> header = split(line, ',');
  std::map<std::string, std::size_t> at;
  for (const char* name : {"time", "x", "y", "z", "vx", "vy", "vz", "roll", "pitch", "yaw"}) {
    const auto found = std::find(header.begin(), header.end(), name);
    if (found == header.end()) throw std::runtime_error(csv.string() + ": no column " + name);
    at[name] = static_cast<std::size_t>(found - header.begin());
  }
  std::vector<nav_msgs::Odometry> messages;
  while (std::getline(text, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> fields = split(line, ',');
    const auto value = [&](const char* name) { return std::stod(fields.at(at[name])); };
    const double time = value("time");
    double sec = std::floor(time);
    double nanosec = std::round((time - sec) * 1e9);
    if (nanosec >= 1e9) sec += 1, nanosec -= 1e9;
    const double roll = value("roll"), pitch = value("pitch"), yaw = value("yaw");
    nav_msgs::Odometry odometry;
    odometry.header.seq = static_cast<std::uint32_t>(messages.size());
    odometry.header.stamp =
        ros::Time(static_cast<std::uint32_t>(sec), static_cast<std::uint32_t>(nanosec));
    odometry.header.frame_id = "map";
    odometry.child_frame_id = "ins";
    odometry.pose.pose.position.x = value("x");
    odometry.pose.pose.position.y = value("y");
    odometry.pose.pose.position.z = value("z");
    // world_from_device = Rz(yaw) Ry(pitch) Rx(roll) as a quaternion, and its matrix.
    const double cr = std::cos(roll / 2), sr = std::sin(roll / 2), cp = std::cos(pitch / 2),
                 sp = std::sin(pitch / 2), cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
    odometry.pose.pose.orientation.w = cr * cp * cy + sr * sp * sy;
    odometry.pose.pose.orientation.x = sr * cp * cy - cr * sp * sy;
    odometry.pose.pose.orientation.y = cr * sp * cy + sr * cp * sy;
    odometry.pose.pose.orientation.z = cr * cp * sy - sr * sp * cy;
    const double Cr = std::cos(roll), Sr = std::sin(roll), Cp = std::cos(pitch),
                 Sp = std::sin(pitch), Cy = std::cos(yaw), Sy = std::sin(yaw);
    const double r[3][3] = {{Cy * Cp, Cy * Sp * Sr - Sy * Cr, Cy * Sp * Cr + Sy * Sr},
                            {Sy * Cp, Sy * Sp * Sr + Cy * Cr, Sy * Sp * Cr - Cy * Sr},
                            {-Sp, Cp * Sr, Cp * Cr}};
    const double v[3] = {value("vx"), value("vy"), value("vz")};
    // The velocity in the device's axes: R^T v.
    double body[3];
    for (int k = 0; k < 3; ++k) body[k] = r[0][k] * v[0] + r[1][k] * v[1] + r[2][k] * v[2];
    odometry.twist.twist.linear.x = body[0];
    odometry.twist.twist.linear.y = body[1];
    odometry.twist.twist.linear.z = body[2];
    messages.push_back(odometry);
  }
  return messages;
}

// header.stamp from a sweep's file name, by integer arithmetic: "000012.300000.pcd" -> 12 s,
// 300000000 ns.
ros::Time stamp_of_name(const std::string& name) {
  const std::string stem = fs::path(name).stem().string();  // 000012.300000
  const std::size_t dot = stem.find('.');
  const std::string sec = stem.substr(0, dot);
  const std::string fraction = dot == std::string::npos ? "" : stem.substr(dot + 1);
  const auto digits = [](const std::string& s) {
    return !s.empty() &&
           std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!digits(sec) || !digits(fraction) || fraction.size() > 9) {
    throw std::runtime_error(name + ": not a sweep name (SECONDS.FRACTION.pcd)");
  }
  return ros::Time(
      static_cast<std::uint32_t>(std::stoul(sec)),
      static_cast<std::uint32_t>(std::stoul(fraction + std::string(9 - fraction.size(), '0'))));
}

// One binary PCD file of x2car's fields (header lines up to "DATA binary\n", then WIDTH x HEIGHT
// packed points of 22 bytes) as a PointCloud2 of the same bytes.
sensor_msgs::PointCloud2 read_sweep(const fs::path& path) {
  const std::string bytes = read_file(path);
  const std::string data_line = "DATA binary\n";
  const std::size_t end = bytes.find(data_line);
  if (end == std::string::npos) {
    throw std::runtime_error(path.string() + ": no \"DATA binary\" line");
  }
  std::map<std::string, std::string> header;
  for (const std::string& line : split(bytes.substr(0, end), '\n')) {
    const std::size_t space = line.find(' ');
    if (!line.empty() && line[0] != '#' && space != std::string::npos) {
      header[line.substr(0, space)] = line.substr(space + 1);
    }
  }
  if (header["FIELDS"] != "x y z intensity ring t" || header["SIZE"] != "4 4 4 4 2 4" ||
      header["TYPE"] != "F F F F U F") {
    throw std::runtime_error(path.string() + ": not x2car's fields (x y z intensity ring t)");
  }
  const std::size_t count =
      std::stoul(header["WIDTH"]) * std::stoul(header.count("HEIGHT") ? header["HEIGHT"] : "1");
  const std::size_t start = end + data_line.size();
  if (bytes.size() < start + count * 22) throw std::runtime_error(path.string() + ": cut short");

  sensor_msgs::PointCloud2 cloud;
  cloud.header.stamp = stamp_of_name(path.filename().string());
  cloud.header.frame_id = "lidar";
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(count);
  using sensor_msgs::PointField;
  const std::pair<const char*, std::uint8_t> fields[] = {
      {"x", PointField::FLOAT32},         {"y", PointField::FLOAT32},   {"z", PointField::FLOAT32},
      {"intensity", PointField::FLOAT32}, {"ring", PointField::UINT16}, {"t", PointField::FLOAT32}};
  std::uint32_t offset = 0;
  for (const auto& [name, datatype] : fields) {
    PointField field;
    field.name = name;
    field.offset = offset;
    field.datatype = datatype;
    field.count = 1;
    cloud.fields.push_back(field);
    offset += datatype == PointField::UINT16 ? 2 : 4;
  }
  cloud.is_bigendian = false;
  cloud.point_step = 22;
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.data.assign(bytes.begin() + static_cast<std::ptrdiff_t>(start),
                    bytes.begin() + static_cast<std::ptrdiff_t>(start + count * 22));
  cloud.is_dense = false;
  return cloud;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string usage =
      "usage: write_ros1_bag DRIVE_DIR OUT.bag [--compression none|lz4|bz2] [--truncate]";
  std::vector<std::string> positional;
  std::string compression = "none";
  bool truncate = false, unknown = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--compression" && i + 1 < argc) {
      compression = argv[++i];
    } else if (arg == "--truncate") {
      truncate = true;
    } else {
      unknown |= arg.rfind("--", 0) == 0;
      positional.push_back(arg);
    }
  }
  const std::map<std::string, rosbag::compression::CompressionType> compressions = {
      {"none", rosbag::compression::Uncompressed},
      {"lz4", rosbag::compression::LZ4},
      {"bz2", rosbag::compression::BZ2}};
  if (unknown || positional.size() != 2 || !compressions.count(compression)) {
    std::cerr << usage << "\n";
    return 2;
  }
  try {
    const fs::path drive = positional[0], out = positional[1];
    std::vector<nav_msgs::Odometry> odometry;
    if (fs::exists(drive / "ins" / "ins.csv")) odometry = read_ins(drive / "ins" / "ins.csv");
    std::vector<fs::path> sweeps;
    if (fs::is_directory(drive / "lidar")) {
      for (const auto& entry : fs::directory_iterator(drive / "lidar")) {
        if (entry.path().extension() == ".pcd") sweeps.push_back(entry.path());
      }
    }
    std::sort(sweeps.begin(), sweeps.end());
    if (odometry.empty() && sweeps.empty()) {
      throw std::runtime_error(drive.string() + ": no ins/ins.csv, no lidar/*.pcd");
    }

    rosbag::Bag bag(out.string(), rosbag::bagmode::Write);
    bag.setCompression(compressions.at(compression));
    const auto bag_time = [](const ros::Time& stamp) { return std::max(stamp, ros::TIME_MIN); };
    // In time order, the odometry first at one stamp; each sweep read when its turn comes.
    std::size_t next = 0;
    const auto write_odometry_until = [&](const ros::Time& until) {
      for (; next < odometry.size() && odometry[next].header.stamp <= until; ++next) {
        bag.write("/odom", bag_time(odometry[next].header.stamp), odometry[next]);
      }
    };
    for (std::size_t k = 0; k < sweeps.size(); ++k) {
      sensor_msgs::PointCloud2 cloud = read_sweep(sweeps[k]);
      cloud.header.seq = static_cast<std::uint32_t>(k);
      write_odometry_until(cloud.header.stamp);
      bag.write("/points", bag_time(cloud.header.stamp), cloud);
    }
    write_odometry_until(ros::TIME_MAX);
    bag.close();
    if (truncate) fs::resize_file(out, fs::file_size(out) * 6 / 10);
  } catch (const std::exception& error) {
    std::cerr << "write_ros1_bag: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
