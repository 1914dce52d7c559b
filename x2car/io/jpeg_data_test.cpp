#include "x2car/io/jpeg_data.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace x2car::io {
namespace {

using JpegBytes = std::vector<unsigned char>;

void append(JpegBytes& bytes, const JpegBytes& more) {
  bytes.insert(bytes.end(), more.begin(), more.end());
}

// The marker layout of a baseline JPEG, with an APP1 segment that holds a thumbnail (a whole JPEG
// of its own), a scan whose entropy-coded data holds a stuffed 0xFF 0x00 and a restart marker, and
// `tail` after EOI.
JpegBytes jpeg(const JpegBytes& tail = {}) {
  JpegBytes bytes = {0xFF, 0xD8};                               // SOI
  append(bytes, {0xFF, 0xE0, 0x00, 0x06, 'J', 'F', 'I', 'F'});  // APP0
  append(bytes, {0xFF, 0xE1, 0x00, 0x0B,                        // APP1, 9 bytes: a thumbnail's
                 0xFF, 0xD8, 0xFF, 0xDA, 0x00, 0x02, 0x11,      // SOI, SOS, ...
                 0xFF, 0xD9});                                  // ... and EOI
  append(bytes, {0xFF, 0xC0, 0x00, 0x04, 0x08, 0x00});          // SOF0
  append(bytes, {0xFF, 0xDA, 0x00, 0x03, 0x01});                // SOS
  append(bytes, {0x12, 0x34, 0xFF, 0x00, 0x56, 0xFF, 0xD0, 0x78, 0x9A});  // scan data
  append(bytes, {0xFF, 0xFF, 0xD9});                                      // fill, EOI
  append(bytes, tail);
  return bytes;
}

TEST(JpegData, AWholeJpegReachesItsEnd) {
  EXPECT_TRUE(starts_as_jpeg(jpeg()));
  EXPECT_EQ(jpeg_break_offset(jpeg()), std::nullopt);
  // Data after the end (a motion photo's video) is not looked at.
  EXPECT_EQ(jpeg_break_offset(jpeg({0x00, 0x00, 0x00, 0x18, 'f', 't', 'y', 'p'})), std::nullopt);
}

// Cut anywhere before its EOI, the data is not whole, also where the cut leaves the thumbnail's
// own EOI (which a search for 0xFF 0xD9 would have taken for the end).
TEST(JpegData, AJpegCutShortAnywhereIsFound) {
  const JpegBytes whole = jpeg();
  for (std::size_t size = 0; size < whole.size(); ++size) {
    const JpegBytes cut(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(size));
    const std::optional<std::size_t> offset = jpeg_break_offset(cut);
    ASSERT_TRUE(offset.has_value()) << size;
    EXPECT_LE(*offset, size);
  }
}

TEST(JpegData, BrokenMarkersAndOtherDataAreNotWhole) {
  EXPECT_FALSE(starts_as_jpeg(JpegBytes{0x89, 'P', 'N', 'G'}));
  EXPECT_EQ(jpeg_break_offset(JpegBytes{0x89, 'P', 'N', 'G'}), 0U);
  JpegBytes garbled = jpeg();
  garbled[2] = 0x12;  // where APP0's marker should be
  EXPECT_EQ(jpeg_break_offset(garbled), 2U);
  JpegBytes short_length = jpeg();
  short_length[5] = 0x01;  // APP0's length below its own two bytes
  EXPECT_EQ(jpeg_break_offset(short_length), 4U);
  EXPECT_EQ(describe_jpeg_break(100, 100),
            "a JPEG cut short: its data ends after 100 bytes, before its end-of-image marker");
  EXPECT_EQ(describe_jpeg_break(4, 100),
            "a JPEG cut short: its markers break off at byte 4 of 100");
}

}  // namespace
}  // namespace x2car::io
