// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the byte code of collection_index.h's models (see the format there), shared by the
// index and its file reader. Internal: not an interface of the library.
#pragma once

#include "canonform/views/bag_of_features.h"

#include <cstdint>
#include <string>
#include <vector>

namespace canonform::retrieval {
namespace detail {

constexpr int kMaxViews = 80;  // views per model an index holds

/// Appends an unsigned LEB128 number.
void put_leb128(std::vector<std::uint8_t>& out, std::uint32_t v);
/// Appends one view's histogram in the byte code (InputError naming `model` on a histogram that is
/// not sorted, a word outside [0, words), a count that is not a positive integer or a view of more
/// than 65535 keypoints).
void encode_view(const views::Histogram& h, int words, std::vector<std::uint8_t>& out,
                 const std::string& model);
/// True if [p, end) is exactly `views` well-formed views of words below `words`.
bool check_model(const std::uint8_t* p, const std::uint8_t* end, int views, int words);
/// The `views` histograms of the model whose bytes start at `p` (checked before).
void unpack(const std::uint8_t* p, int views, std::vector<views::Histogram>& out);

}  // namespace detail
}  // namespace canonform::retrieval
