// Whether JPEG data is whole, by its markers.
//
// A JPEG cut short (a file truncated in copying, a camera that lost power while writing, a message
// that lost its tail) decodes without an error: the decoder fills the missing rows with grey and
// says so only on its own log, so such a frame would pass for a good one and its grey edge would
// give lines. The markers are walked from the start of image (SOI) to its end (EOI): each segment
// by its length (so an APP1 segment's Exif thumbnail, itself a whole JPEG, is stepped over), each
// scan's entropy-coded data to the next marker (inside it a 0xFF byte is always followed by 0x00
// or a restart marker). Data after EOI (a motion photo's video) is not looked at.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>

namespace x2car::io {

// Whether the data starts as a JPEG does (SOI, 0xFF 0xD8).
bool starts_as_jpeg(std::span<const unsigned char> data);

// nullopt when the data is a whole JPEG (its EOI reached); else the byte offset where it ends
// before its EOI or where its markers break off. Data that does not start as a JPEG gives 0.
std::optional<std::size_t> jpeg_break_offset(std::span<const unsigned char> data);

// What is wrong with the data when it starts as a JPEG and is not whole ("a JPEG cut short: ...",
// describe_jpeg_break); nullopt when it is whole or no JPEG at all (another decoder's concern).
std::optional<std::string> jpeg_cut_short(std::span<const unsigned char> data);

// For an error message: "a JPEG cut short: its data ends after 40765 bytes, before its end-of-image
// marker", or "... its markers break off at byte 812 of 40765".
std::string describe_jpeg_break(std::size_t offset, std::size_t size);

}  // namespace x2car::io
