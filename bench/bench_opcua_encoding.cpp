// OPC UA binary encoding speed (OPC 10000-6 §5.2): a ReadResponse with 100 DataValues (Double
// values with status and both timestamps, as a server returns them for a polling client),
// encoded and decoded with the service-message envelope. The peer in the same run is a plain
// memcpy of the same bytes: the floor any encoder is measured against.
//
//   build/release/bench/bench_opcua_encoding
#include <cstring>

#include <benchmark/benchmark.h>

#include "sf/opcua/encoding.hpp"

namespace {

using namespace sf::opcua;

constexpr std::size_t kValues = 100;

ReadResponse make_response() {
  ReadResponse response;
  response.response_header.timestamp = DateTime{133'600'000'000'000'000};
  response.response_header.request_handle = 42;
  response.results.reserve(kValues);
  for (std::size_t i = 0; i < kValues; ++i) {
    DataValue value(Variant(20.0 + static_cast<double>(i) * 0.25));
    value.status = i % 10 == 9 ? status::UncertainLastUsableValue : status::Good;
    value.source_timestamp = DateTime{133'600'000'000'000'000 + static_cast<std::int64_t>(i)};
    value.server_timestamp = DateTime{133'600'000'000'100'000};
    response.results.push_back(value);
  }
  return response;
}

const sf::Bytes& encoded_response() {
  static const sf::Bytes bytes = *encode_message(make_response());
  return bytes;
}

void set_counters(benchmark::State& state) {
  const auto iterations = static_cast<std::int64_t>(state.iterations());
  state.SetItemsProcessed(iterations * static_cast<std::int64_t>(kValues));
  state.SetBytesProcessed(iterations * static_cast<std::int64_t>(encoded_response().size()));
}

// Encoding into a buffer that is reused, as a secure channel reuses its chunk buffer.
void BM_EncodeReadResponse(benchmark::State& state) {
  const ReadResponse response = make_response();
  sf::Bytes buffer;
  buffer.reserve(encoded_response().size());
  for (auto _ : state) {
    buffer.clear();
    sf::ByteWriter writer(buffer);
    if (!encode_message(response, writer).ok()) {
      state.SkipWithError("encode failed");
    }
    benchmark::DoNotOptimize(buffer.data());
  }
  set_counters(state);
}
BENCHMARK(BM_EncodeReadResponse);

// Decoding into a fresh Message each time (what decode_message does).
void BM_DecodeReadResponse(benchmark::State& state) {
  const sf::Bytes& bytes = encoded_response();
  for (auto _ : state) {
    auto message = decode_message(bytes);
    if (!message.ok()) {
      state.SkipWithError("decode failed");
    }
    benchmark::DoNotOptimize(message);
  }
  set_counters(state);
}
BENCHMARK(BM_DecodeReadResponse);

// Decoding into a ReadResponse that is reused: arrays and strings keep their capacity.
void BM_DecodeReadResponseReused(benchmark::State& state) {
  const sf::Bytes& bytes = encoded_response();
  ReadResponse response;
  for (auto _ : state) {
    sf::ByteReader reader(sf::ByteSpan(bytes).subspan(4));  // after the encoding NodeId
    if (!decode(reader, response).ok()) {
      state.SkipWithError("decode failed");
    }
    benchmark::DoNotOptimize(response.results.data());
  }
  set_counters(state);
}
BENCHMARK(BM_DecodeReadResponseReused);

// The peer: copying the encoded bytes.
void BM_PeerMemcpy(benchmark::State& state) {
  const sf::Bytes& bytes = encoded_response();
  sf::Bytes copy(bytes.size());
  for (auto _ : state) {
    std::memcpy(copy.data(), bytes.data(), bytes.size());
    benchmark::DoNotOptimize(copy.data());
    benchmark::ClobberMemory();
  }
  set_counters(state);
}
BENCHMARK(BM_PeerMemcpy);

}  // namespace

BENCHMARK_MAIN();
