#include "x2car/io/bag_tf.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <memory>
#include <set>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/ros_message.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr const char* kTfMessage = "tf2_msgs/TFMessage";

// tf2_msgs/TFMessage: geometry_msgs/TransformStamped[] (header, child_frame_id, translation,
// rotation x y z w).
void decode_tf_message(RosMessageReader& message, const std::string& topic,
                       std::vector<FrameTransform>& out) {
  const std::uint32_t count = message.uint32("transforms");
  for (std::uint32_t i = 0; i < count; ++i) {
    FrameTransform transform;
    transform.topic = topic;
    transform.parent = message.header().frame_id;
    transform.child = message.string("transforms.child_frame_id");
    Eigen::Vector3d translation;
    translation.x() = message.float64("transforms.transform.translation.x");
    translation.y() = message.float64("transforms.transform.translation.y");
    translation.z() = message.float64("transforms.transform.translation.z");
    const double qx = message.float64("transforms.transform.rotation.x");
    const double qy = message.float64("transforms.transform.rotation.y");
    const double qz = message.float64("transforms.transform.rotation.z");
    const double qw = message.float64("transforms.transform.rotation.w");
    const Eigen::Quaterniond q(qw, qx, qy, qz);
    if (!translation.allFinite() || !std::isfinite(q.norm()) || std::abs(q.norm() - 1.0) > 1e-2) {
      throw InputError(message.source(), 0, "transforms." + transform.child,
                       "not a finite translation and unit quaternion");
    }
    // tf frames are named with or without a leading slash (ROS 1's tf had it).
    for (std::string* name : {&transform.parent, &transform.child}) {
      if (name->starts_with('/')) name->erase(0, 1);
    }
    transform.parent_from_child.linear() = q.normalized().toRotationMatrix();
    transform.parent_from_child.translation() = translation;
    out.push_back(std::move(transform));
  }
}

bool is_static_topic(const std::string& topic) { return topic.ends_with("tf_static"); }

}  // namespace

std::vector<FrameTransform> read_bag_transforms(const std::filesystem::path& path,
                                                bool allow_truncated) {
  const std::string file = path.string();
  const std::unique_ptr<BagFile> bag = open_bag(path, {.allow_truncated = allow_truncated});
  const auto wanted = [](const BagTopic& topic) { return ros_type_is(topic.type, kTfMessage); };
  std::vector<FrameTransform> all;
  std::vector<std::int64_t> counts;
  bag->scan(wanted, [&](const BagMessage& message) {
    counts.resize(bag->topics().size(), 0);
    const std::int64_t count = ++counts[message.topic];
    const BagTopic& topic = bag->topics()[message.topic];
    if (!wanted(topic)) return;
    RosMessageReader reader(message.data, ros_encoding_of(topic, path),
                            fmt::format("{} ({} message {})", file, topic.name, count));
    decode_tf_message(reader, topic.name, all);
  });
  // Per child: a static transform wins; else the first seen.
  std::map<std::string, FrameTransform> by_child;
  for (FrameTransform& transform : all) {
    const auto known = by_child.find(transform.child);
    if (known == by_child.end() ||
        (is_static_topic(transform.topic) && !is_static_topic(known->second.topic))) {
      by_child[transform.child] = std::move(transform);
    }
  }
  std::vector<FrameTransform> out;
  for (auto& [child, transform] : by_child) out.push_back(std::move(transform));
  return out;
}

std::optional<Eigen::Isometry3d> chain_transform(const std::vector<FrameTransform>& transforms,
                                                 const std::string& root,
                                                 const std::string& frame) {
  std::map<std::string, const FrameTransform*> parent_of;
  for (const FrameTransform& transform : transforms) parent_of[transform.child] = &transform;
  Eigen::Isometry3d root_from_frame = Eigen::Isometry3d::Identity();
  std::set<std::string> seen;
  std::string at = frame;
  while (at != root) {
    const auto link = parent_of.find(at);
    if (link == parent_of.end() || !seen.insert(at).second) return std::nullopt;
    root_from_frame = link->second->parent_from_child * root_from_frame;
    at = link->second->parent;
  }
  return root_from_frame;
}

std::optional<MountingPrior> mounting_prior_from_bag(const std::filesystem::path& bag,
                                                     const std::string& frame,
                                                     const std::string& root) {
  std::string child = frame;
  if (child.starts_with('/')) child.erase(0, 1);
  if (child.empty()) return std::nullopt;
  const std::vector<FrameTransform> transforms = read_bag_transforms(bag);
  const std::optional<Eigen::Isometry3d> root_from_frame = chain_transform(transforms, root, child);
  if (!root_from_frame) return std::nullopt;
  std::set<std::string> topics;
  for (const FrameTransform& transform : transforms) topics.insert(transform.topic);
  MountingPrior prior;
  prior.parent = root;
  prior.child = child;
  prior.source = fmt::format("{} {}", bag.string(),
                             join(std::vector<std::string>(topics.begin(), topics.end())));
  prior.angles = euler_from_rotation(root_from_frame->linear());
  prior.translation = root_from_frame->translation();
  return prior;
}

}  // namespace x2car::io
