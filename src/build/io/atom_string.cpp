#include "build/io/atom_string.hpp"

#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace surftrace::build {
namespace {

// Long texts in chunks of 4,096 that never move, so a reader needs no lock: it holds an index
// only after the interning that wrote the text (the record carrying it was made after).
constexpr std::size_t kChunkBits = 12;
constexpr std::size_t kChunkSize = std::size_t{1} << kChunkBits;
constexpr std::size_t kChunkCount = std::size_t{1} << 16;  // 2^28 distinct long texts at most

struct LongTexts {
  std::mutex mutex;
  std::unordered_map<std::string_view, std::uint32_t> index;  // views into the chunks
  std::array<std::atomic<std::string*>, kChunkCount> chunks{};
  std::vector<std::unique_ptr<std::string[]>> owned;
  std::uint32_t count = 0;
};

LongTexts& longTexts() {
  static LongTexts* table = new LongTexts;  // never destroyed: records may outlive static destruction
  return *table;
}

}  // namespace

std::uint32_t AtomString::internLong(std::string_view text) {
  LongTexts& t = longTexts();
  const std::lock_guard lock(t.mutex);
  if (const auto it = t.index.find(text); it != t.index.end()) return it->second;
  const std::uint32_t i = t.count;
  const std::size_t chunk = i >> kChunkBits;
  if (chunk >= kChunkCount)
    throw std::length_error("more than " + std::to_string(kChunkCount * kChunkSize) +
                            " distinct atom, residue, chain or segment names longer than 7 characters");
  std::string* slots = t.chunks[chunk].load(std::memory_order_acquire);
  if (slots == nullptr) {
    slots = t.owned.emplace_back(std::make_unique<std::string[]>(kChunkSize)).get();
    t.chunks[chunk].store(slots, std::memory_order_release);
  }
  std::string& stored = slots[i & (kChunkSize - 1)];
  stored.assign(text);
  t.index.emplace(std::string_view(stored), i);
  ++t.count;
  return i;
}

std::string_view AtomString::longText(std::uint32_t index) {
  const std::string* slots = longTexts().chunks[index >> kChunkBits].load(std::memory_order_acquire);
  return slots[index & (kChunkSize - 1)];
}

}  // namespace surftrace::build
