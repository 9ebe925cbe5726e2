// SES block concatenation: per-thread pass buffers gathered in atom order, and segments spliced on update.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "build/ses/ses_types.hpp"

namespace surftrace::build::detail {

// Assembly: every array is a concatenation of per-atom segments in atom order (per probe
// for the clipping planes), so a full build concatenates the pieces and a partial update
// splices fresh segments between the old ones.

// Runs body(k, scratch, buffer) for k in [0, count) in parallel chunks of kBlock, recording
// where each chunk's output lies.
template <class Buf, class BufOf, class Body>
void runChunks(tbb::enumerable_thread_specific<Scratch>& tls, std::size_t count, std::vector<Piece<Buf>>& pieces,
               BufOf bufOf, Body body) {
  for (Scratch& s : tls) bufOf(s).clear();
  const std::size_t chunks = (count + kBlock - 1) / kBlock;
  pieces.assign(chunks, Piece<Buf>{});
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    Scratch& s = tls.local();
    Buf& buf = bufOf(s);
    if (buf.size(2) == 0) buf.reserve(count);  // this thread's first chunk of the pass
    Piece<Buf>& piece = pieces[c];
    piece.buf = &buf;
    for (int g = 0; g < 3; ++g) piece.begin[static_cast<std::size_t>(g)] = buf.size(g);
    for (std::size_t k = c * kBlock; k < std::min(count, (c + 1) * kBlock); ++k) body(k, s, buf);
    for (int g = 0; g < 3; ++g) piece.end[static_cast<std::size_t>(g)] = buf.size(g);
  });
}

// Where each piece's group g goes in the concatenation; returns the total.
template <class Buf>
std::size_t pieceOffsets(const std::vector<Piece<Buf>>& pieces, std::size_t g, std::vector<std::size_t>& offset) {
  offset.resize(pieces.size() + 1);
  offset[0] = 0;
  for (std::size_t c = 0; c < pieces.size(); ++c) offset[c + 1] = offset[c] + (pieces[c].end[g] - pieces[c].begin[g]);
  return offset.back();
}

// One field of a pass buffer and where its concatenation goes.
template <class Buf, class T> struct Field {
  std::vector<T> Buf::*member;
  std::vector<T>* to;
  std::size_t group;
};

// Concatenates the fields of the pieces, in chunk order, one field at a time.
// forEachField(f) calls f(Field{...}) once for every field to gather.
// A field whose concatenation is large has its per-thread sources freed as soon as it is
// copied: on a full build of a large molecule the sources and the destinations together
// were the SES build's peak memory, and the buffers would otherwise stay resident through
// the passes after. Small fields keep their capacity, so that the small passes of a
// trajectory's updates reuse it instead of allocating per frame.
template <class Buf, class ForEachField>
void gatherPieces(const std::vector<Piece<Buf>>& pieces, std::array<std::vector<std::size_t>, 3>& offset,
                  ForEachField&& forEachField) {
  constexpr std::size_t kReleaseBytes = std::size_t{1} << 20;
  for (std::size_t g = 0; g < 3; ++g) pieceOffsets(pieces, g, offset[g]);
  std::vector<Buf*> sources;  // the distinct thread buffers, in piece order
  for (const Piece<Buf>& piece : pieces)
    if (std::find(sources.begin(), sources.end(), piece.buf) == sources.end()) sources.push_back(piece.buf);
  forEachField([&](const auto& field) {
    const std::size_t g = field.group;
    field.to->resize(offset[g].back());
    tbb::parallel_for(std::size_t{0}, pieces.size(), [&](std::size_t c) {
      const Piece<Buf>& piece = pieces[c];
      const auto& from = (*piece.buf).*(field.member);
      std::copy(from.begin() + static_cast<std::ptrdiff_t>(piece.begin[g]),
                from.begin() + static_cast<std::ptrdiff_t>(piece.end[g]),
                field.to->begin() + static_cast<std::ptrdiff_t>(offset[g][c]));
    });
    using Vec = std::remove_reference_t<decltype(*field.to)>;
    if (offset[g].back() * sizeof(typename Vec::value_type) >= kReleaseBytes)
      for (Buf* buf : sources) Vec().swap((*buf).*(field.member));
  });
}

// Segment starts from per-item lengths: begin[0] = 0, begin[i + 1] = begin[i] + len[i].
inline void prefix(std::span<const std::uint32_t> len, std::vector<std::uint32_t>& begin) {
  begin.resize(len.size() + 1);
  begin[0] = 0;
  for (std::size_t i = 0; i < len.size(); ++i) begin[i + 1] = begin[i] + len[i];
}

// The arrays after replacing the segments of the atoms in `changed` (ascending): old
// segments at oldBegin, fresh ones (one per changed atom, in order) at freshBegin, new
// starts at newBegin (see newStarts). Unchanged runs move in one copy each.
struct Splice {
  std::span<const std::uint32_t> oldBegin, newBegin, changed, freshBegin;

  template <class T> void operator()(std::vector<T>& arr, const std::vector<T>& fresh, std::vector<T>& tmp) const {
    const std::size_t n = oldBegin.size() - 1;
    tmp.resize(newBegin[n]);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, changed.size() + 1, 32), [&](const auto& range) {
      for (std::size_t c = range.begin(); c != range.end(); ++c) {
        const std::size_t runBegin = c == 0 ? 0 : changed[c - 1] + 1;
        const std::size_t runEnd = c == changed.size() ? n : changed[c];
        if (runEnd > runBegin)
          std::copy(arr.begin() + oldBegin[runBegin], arr.begin() + oldBegin[runEnd], tmp.begin() + newBegin[runBegin]);
        if (c < changed.size())
          std::copy(fresh.begin() + freshBegin[c], fresh.begin() + freshBegin[c + 1], tmp.begin() + newBegin[changed[c]]);
      }
    });
    arr.swap(tmp);
  }
};

// New segment starts: old lengths for unchanged atoms, fresh lengths for changed ones.
inline void newStarts(std::span<const std::uint32_t> oldBegin, std::span<const std::uint32_t> changed,
               std::span<const std::uint32_t> freshBegin, std::vector<std::uint32_t>& newBegin) {
  const std::size_t n = oldBegin.size() - 1;
  newBegin.resize(n + 1);
  newBegin[0] = 0;
  std::size_t c = 0;
  for (std::size_t x = 0; x < n; ++x) {
    std::uint32_t len;
    if (c < changed.size() && changed[c] == x) {
      len = freshBegin[c + 1] - freshBegin[c];
      ++c;
    } else {
      len = oldBegin[x + 1] - oldBegin[x];
    }
    newBegin[x + 1] = newBegin[x] + len;
  }
}

template <class T> bool sameBits(std::span<const T> a, std::span<const T> b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace surftrace::build::detail
