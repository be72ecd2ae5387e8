// NumericRange (OPC 10000-4 §7.27): parsing, reading a sub-range of an array, matrix or string,
// and writing into one.
#include <charconv>
#include <string>
#include <type_traits>
#include <vector>

#include "sf/opcua/server/services.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server {

namespace {

template <typename T>
constexpr bool kIsText = std::is_same_v<T, String> || std::is_same_v<T, ByteString>;

Error invalid(std::string_view text, std::string_view why) {
  return status_error(status::BadIndexRangeInvalid,
                      "index range '" + std::string(text) + "': " + std::string(why));
}

Error no_data(std::string_view why) {
  return status_error(status::BadIndexRangeNoData, std::string(why));
}

Result<std::uint32_t> parse_index(std::string_view all, std::string_view digits) {
  std::uint32_t value = 0;
  const auto* end = digits.data() + digits.size();
  auto [ptr, ec] = std::from_chars(digits.data(), end, value);
  if (digits.empty() || ec != std::errc() || ptr != end) {
    return invalid(all, "expected an unsigned number");
  }
  return value;
}

// The shape of value as the range sees it: the matrix dimensions, or {length} of an array.
std::vector<std::size_t> shape_of(const Variant& value) {
  std::vector<std::size_t> shape;
  for (auto d : value.array_dimensions()) {
    shape.push_back(d > 0 ? static_cast<std::size_t>(d) : 0U);
  }
  if (shape.empty()) {
    shape.push_back(value.array_length());
  }
  return shape;
}

// The flat (row-major) indices of the elements a range selects and the selection's shape.
// clip: reading clips `high` to the data; writing needs the whole range to exist.
struct Selection {
  std::vector<std::size_t> indices;
  std::vector<std::int32_t> shape;
};

Result<Selection> select(const std::vector<std::size_t>& shape,
                         const std::vector<NumericRange::Dimension>& dims, bool clip) {
  if (dims.size() != shape.size()) {
    return no_data("the index range has " + std::to_string(dims.size()) + " dimensions, the value " +
                   std::to_string(shape.size()));
  }
  std::vector<std::size_t> low(dims.size());
  std::vector<std::size_t> high(dims.size());
  Selection s;
  for (std::size_t d = 0; d < dims.size(); ++d) {
    low[d] = dims[d].low;
    high[d] = dims[d].high;
    if (low[d] >= shape[d] || (!clip && high[d] >= shape[d])) {
      return no_data("index " + std::to_string(clip ? low[d] : high[d]) + " is beyond the length " +
                     std::to_string(shape[d]));
    }
    high[d] = std::min(high[d], shape[d] - 1);
    s.shape.push_back(static_cast<std::int32_t>(high[d] - low[d] + 1));
  }
  std::vector<std::size_t> at = low;
  for (;;) {
    std::size_t flat = 0;
    for (std::size_t d = 0; d < dims.size(); ++d) {
      flat = flat * shape[d] + at[d];
    }
    s.indices.push_back(flat);
    std::size_t d = dims.size();
    while (d > 0 && at[d - 1] == high[d - 1]) {
      at[d - 1] = low[d - 1];
      --d;
    }
    if (d == 0) {
      return s;
    }
    ++at[d - 1];
  }
}

template <typename T>
T text_slice(const T& text, const NumericRange::Dimension& dim) {
  if constexpr (std::is_same_v<T, String>) {
    if (dim.low >= text.size()) {
      return String("");
    }
    return String(text.str().substr(dim.low, dim.high - dim.low + 1));
  } else {
    if (dim.low >= text.size()) {
      return ByteString(Bytes{});
    }
    const auto& b = text.bytes();
    const std::size_t end = std::min<std::size_t>(b.size(), std::size_t{dim.high} + 1);
    return ByteString(Bytes(b.begin() + dim.low, b.begin() + static_cast<std::ptrdiff_t>(end)));
  }
}

template <typename T>
Result<Variant> slice_array(const Variant& value, const Array<T>& array, const NumericRange& range) {
  auto shape = shape_of(value);
  // One extra dimension on an array of strings selects characters/bytes of each element.
  const bool sub_text = kIsText<T> && range.dimensions.size() == shape.size() + 1;
  std::vector<NumericRange::Dimension> dims = range.dimensions;
  if (sub_text) {
    dims.pop_back();
  }
  auto selection = select(shape, dims, true);
  if (!selection) {
    return selection.error();
  }
  Array<T> out;
  out.reserve(selection->indices.size());
  for (auto i : selection->indices) {
    if constexpr (kIsText<T>) {
      out.push_back(sub_text ? text_slice(array[i], range.dimensions.back()) : array[i]);
    } else {
      out.push_back(array[i]);
    }
  }
  Variant result(std::move(out));
  if (selection->shape.size() > 1) {
    SF_TRY(result.set_array_dimensions(selection->shape));
  }
  return result;
}

template <typename T>
Result<Variant> patch_array(const Variant& value, const Array<T>& array, const NumericRange& range,
                            const Variant& patch) {
  const auto* source = patch.array_if<T>();
  if (source == nullptr) {
    return status_error(status::BadTypeMismatch,
                        "the value written into an index range is not an array of the "
                        "same type");
  }
  auto selection = select(shape_of(value), range.dimensions, false);
  if (!selection) {
    return selection.error();
  }
  if (source->size() != selection->indices.size()) {
    return status_error(status::BadTypeMismatch,
                        "the index range selects " + std::to_string(selection->indices.size()) +
                            " elements, the value has " + std::to_string(source->size()));
  }
  Array<T> out = array;
  for (std::size_t i = 0; i < source->size(); ++i) {
    out[selection->indices[i]] = (*source)[i];
  }
  Variant result(std::move(out));
  if (value.is_matrix()) {
    SF_TRY(result.set_array_dimensions(value.array_dimensions()));
  }
  return result;
}

template <typename T>
Result<Variant> patch_text(const T& text, const NumericRange& range, const Variant& patch) {
  const auto* source = patch.get_if<T>();
  if (source == nullptr) {
    return status_error(status::BadTypeMismatch, "the value written into a string range is not of its type");
  }
  if (range.dimensions.size() != 1) {
    return no_data("a string has one dimension");
  }
  const auto& dim = range.dimensions[0];
  if (dim.high >= text.size()) {
    return no_data("index " + std::to_string(dim.high) + " is beyond the length " +
                   std::to_string(text.size()));
  }
  if (source->size() != std::size_t{dim.high} - dim.low + 1) {
    return status_error(status::BadTypeMismatch, "the value does not have the length of the range");
  }
  if constexpr (std::is_same_v<T, String>) {
    std::string out = text.str();
    out.replace(dim.low, source->size(), source->str());
    return Variant(String(std::move(out)));
  } else {
    Bytes out = text.bytes();
    std::copy(source->bytes().begin(), source->bytes().end(), out.begin() + dim.low);
    return Variant(ByteString(std::move(out)));
  }
}

}  // namespace

Result<NumericRange> parse_numeric_range(const String& text) {
  NumericRange range;
  const std::string_view all = text.view();
  if (all.empty()) {
    return range;
  }
  std::string_view rest = all;
  while (true) {
    const auto comma = rest.find(',');
    const std::string_view part = rest.substr(0, comma);
    const auto colon = part.find(':');
    NumericRange::Dimension dim;
    auto low = parse_index(all, part.substr(0, colon));
    if (!low) {
      return low.error();
    }
    dim.low = dim.high = *low;
    if (colon != std::string_view::npos) {
      auto high = parse_index(all, part.substr(colon + 1));
      if (!high) {
        return high.error();
      }
      // OPC 10000-4 §7.27: in "low:high" low is less than high.
      if (*high <= *low) {
        return invalid(all, "the upper bound must exceed the lower one");
      }
      dim.high = *high;
    }
    range.dimensions.push_back(dim);
    if (comma == std::string_view::npos) {
      return range;
    }
    rest.remove_prefix(comma + 1);
  }
}

Result<Variant> apply_numeric_range(const Variant& value, const NumericRange& range) {
  if (range.empty()) {
    return value;
  }
  return std::visit(
      [&](const auto& alternative) -> Result<Variant> {
        using A = std::decay_t<decltype(alternative)>;
        if constexpr (IsArray<A>::value) {
          return slice_array(value, alternative, range);
        } else if constexpr (kIsText<A>) {
          if (range.dimensions.size() != 1) {
            return no_data("a string has one dimension");
          }
          if (range.dimensions[0].low >= alternative.size()) {
            return no_data("index " + std::to_string(range.dimensions[0].low) + " is beyond the string");
          }
          return Variant(text_slice(alternative, range.dimensions[0]));
        } else {
          return no_data("an index range needs an array or a string");
        }
      },
      value.storage());
}

Result<Variant> write_numeric_range(const Variant& value, const NumericRange& range, const Variant& patch) {
  if (range.empty()) {
    return patch;
  }
  return std::visit(
      [&](const auto& alternative) -> Result<Variant> {
        using A = std::decay_t<decltype(alternative)>;
        if constexpr (IsArray<A>::value) {
          return patch_array(value, alternative, range, patch);
        } else if constexpr (kIsText<A>) {
          return patch_text(alternative, range, patch);
        } else {
          return no_data("an index range needs an array or a string");
        }
      },
      value.storage());
}

}  // namespace sf::opcua::server
