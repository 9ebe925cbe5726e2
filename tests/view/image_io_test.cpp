// Reading image files whose headers claim more pixels than the file holds or the machine can
// hold: an error naming the file and the claimed size, before anything is allocated for the
// pixels (a 20-byte PFM header claiming 100000x100000 pixels ended in std::bad_alloc).
#include "view/image_io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "temp_dir.hpp"
#include "view/frame_buffers.hpp"

namespace surftrace::view {
namespace {

std::string temp(const std::string& name) { return (::surftrace::test::testTempDir() / name).string(); }

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spit(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

template <class Read> std::string errorOf(Read&& read) {
  try {
    read();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

// A PFM stores its floats raw after a text header: the header's size is checked against the
// file's before any allocation, for one channel and three; a header claiming more than this
// machine's memory is refused on that count first.
TEST(ImageHeaders, APfmClaimingMorePixelsThanItHoldsIsRefused) {
  const std::string huge = temp("huge.pfm"), small = temp("small.pfm");
  spit(huge, std::string("PF\n100000 100000\n-1.0\n") + std::string(12, '\0'));
  const std::string hugeError = errorOf([&] { readImageChannels(huge); });
  EXPECT_EQ(hugeError.rfind(huge + ": ", 0), 0u) << hugeError;
  EXPECT_NE(hugeError.find("its header claims 100000x100000 pixels of 3 channels"), std::string::npos) << hugeError;
  // One row short of a 2x2 grey PFM.
  spit(small, std::string("Pf\n2 2\n-1.0\n") + std::string(8, '\0'));
  EXPECT_EQ(errorOf([&] { readImageChannels(small); }),
            small + ": cannot read its pixels: the file is cut short or damaged (its header promises 2x2 pixels of 1 "
                    "channel, 16 bytes of floats; it holds 8 after its header)");
  // Three channels: 100x10 of them hold 12,000 bytes.
  spit(small, std::string("PF\n100 10\n-1.0\n") + std::string(11999, '\0'));
  EXPECT_NE(errorOf([&] { readImageChannels(small); }).find("100x10 pixels of 3 channels, 12000 bytes of floats; it holds 11999"),
            std::string::npos);
  // Whole, it reads.
  spit(small, std::string("Pf\n2 2\n-1.0\n") + std::string(16, '\0'));
  const ImageChannels image = readImageChannels(small);
  EXPECT_EQ(image.width, 2);
  EXPECT_EQ(image.values, std::vector<float>(4, 0.0f));
}

// The offset of the 16 bytes of a box2i attribute `name` in an EXR header.
std::size_t boxOffset(const std::string& exr, const std::string& name) {
  const std::string key = name + std::string(1, '\0') + "box2i" + std::string(1, '\0');
  const std::size_t at = exr.find(key);
  EXPECT_NE(at, std::string::npos) << name;
  return at + key.size() + 4;  // after the attribute's size
}

// The end of an EXR's header: after its attributes (name, type, i32 size, value), the empty
// name that ends them (OpenEXR's file layout).
std::size_t headerEnd(const std::string& exr) {
  std::size_t at = 8;  // magic and version
  for (;;) {
    const std::size_t name = exr.find('\0', at);
    if (name == at) return at + 1;
    const std::size_t type = exr.find('\0', name + 1);
    std::int32_t size = 0;
    std::memcpy(&size, exr.data() + type + 1, 4);
    at = type + 1 + 4 + static_cast<std::size_t>(size);
  }
}

// An EXR whose data and display windows claim 100000x100000 pixels needs far more memory than
// any machine has: refused by readExr and readImageChannels alike, naming the file and the
// size. It is a 1x1 frame's file with its windows rewritten and its table of chunk offsets
// grown to the 6,250 chunks of 16 rows (ZIP) the claimed height has, each pointing at the one
// chunk there is: OpenEXR opens it (a shorter table it refuses itself).
TEST(ImageHeaders, AnExrClaimingMorePixelsThanMemoryHoldsIsRefused) {
  FrameBuffers frame;
  frame.reset(1, 1);
  const std::string path = temp("huge.exr");
  writeExr(path, frame, {});
  const std::string one = slurp(path);
  const std::size_t end = headerEnd(one);
  std::string bytes = one.substr(0, end);
  for (const char* window : {"dataWindow", "displayWindow"}) {
    const std::int32_t box[4] = {0, 0, 99999, 99999};
    std::memcpy(bytes.data() + boxOffset(bytes, window), box, sizeof box);
  }
  constexpr std::uint64_t kChunks = 100000 / 16;
  const std::uint64_t chunk = end + 8 * kChunks;
  for (std::uint64_t k = 0; k < kChunks; ++k) bytes.append(reinterpret_cast<const char*>(&chunk), 8);
  bytes += one.substr(end + 8);  // the chunk
  spit(path, bytes);
  for (const std::string& what : {errorOf([&] { readExr(path); }), errorOf([&] { readImageChannels(path); })}) {
    EXPECT_EQ(what.rfind(path + ": not enough memory to hold the image it describes: its header claims 100000x100000 "
                                "pixels of 13 channels, which need about ",
                         0),
              0u)
        << what;
    EXPECT_NE(what.find("GiB to read, more than "), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace surftrace::view
