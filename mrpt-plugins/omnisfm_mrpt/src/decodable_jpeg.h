#pragma once
// Whether MRPT 2.5 can decode a stored JPEG image and live. Its decoder
// (CImage::loadFromStreamAsJPEG) keeps libjpeg's default error handler, which ends the process
// with exit() at a fatal error ("Not a JPEG file: starts with 0x61 0x62", "Invalid JPEG file
// structure: two SOI markers"), and allocates the picture from the size in the JPEG's own
// header. This check makes the same libjpeg calls, at an eighth of the size, with an error
// handler that returns.

#include <cstddef>
#include <cstdint>
#include <string>

namespace omnisfm::mrpt_plugin {

// What is wrong with the JPEG bytes for MRPT's decoder, or empty when nothing is.
std::string jpeg_problem(const std::uint8_t* data, std::size_t size);

}  // namespace omnisfm::mrpt_plugin
