#include "chunking.hpp"

#include <fmt/format.h>

#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::detail {
namespace {

// Bytes of the padding field: PaddingSize byte, `padding` bytes, ExtraPaddingSize byte.
std::size_t padding_field(std::size_t padding, bool extra) {
  return 1 + padding + (extra ? 1 : 0);
}

}  // namespace

std::size_t max_body_size(std::uint32_t chunk_size, std::size_t header_size, const MessageCrypto& crypto) {
  const std::size_t sig = crypto.signature_size();
  if (chunk_size <= header_size) {
    return 0;
  }
  const std::size_t room = chunk_size - header_size;
  std::size_t plain_room = room;
  std::size_t overhead = kSequenceHeaderSize + sig;
  if (crypto.encrypts()) {
    // §6.7.2.5: the encrypted part is a whole number of cipher blocks, each carrying one plain
    // block; at least the PaddingSize byte (and ExtraPaddingSize byte) must fit.
    plain_room = (room / crypto.cipher_block_size()) * crypto.plain_block_size();
    overhead += padding_field(0, crypto.extra_padding_byte());
  }
  return plain_room > overhead ? plain_room - overhead : 0;
}

Status append_chunk(Bytes& out, const ChunkSpec& spec, const MessageCrypto& crypto) {
  const std::size_t header_size = kSecureHeaderSize + spec.security_header.size();
  const std::size_t sig = crypto.signature_size();
  std::size_t plain_size = kSequenceHeaderSize + spec.body.size();
  std::size_t padding = 0;
  const bool extra = crypto.encrypts() && crypto.extra_padding_byte();
  if (crypto.encrypts()) {
    const std::size_t block = crypto.plain_block_size();
    const std::size_t unpadded = plain_size + padding_field(0, extra) + sig;
    padding = (block - unpadded % block) % block;
    plain_size += padding_field(padding, extra);
  }
  const std::size_t secured_size =
      crypto.encrypts() ? (plain_size + sig) / crypto.plain_block_size() * crypto.cipher_block_size()
                        : plain_size + sig;
  const std::size_t total = header_size + secured_size;
  if (total > UINT32_MAX) {
    return status_error(status::BadEncodingLimitsExceeded, "chunk larger than 4 GiB");
  }

  const std::size_t start = out.size();
  ByteWriter w(out);
  encode_header(w, MessageHeader{spec.type, spec.chunk, static_cast<std::uint32_t>(total)});
  w.u32(spec.channel_id);
  w.bytes(spec.security_header);
  w.u32(spec.sequence_number);
  w.u32(spec.request_id);
  w.bytes(spec.body);
  if (crypto.encrypts()) {
    const auto low = static_cast<std::uint8_t>(padding & 0xFFU);
    w.u8(low);
    for (std::size_t i = 0; i < padding; ++i) {
      w.u8(low);
    }
    if (extra) {
      w.u8(static_cast<std::uint8_t>(padding >> 8U));
    }
  }
  if (sig == 0 && !crypto.encrypts()) {
    return {};  // SecurityPolicy None: the chunk is complete
  }
  auto signature = crypto.sign(ByteSpan(out).subspan(start));
  if (!signature.ok()) {
    out.resize(start);
    return signature.error();
  }
  if (signature->size() != sig) {
    out.resize(start);
    return status_error(status::BadInternalError, "signature of unexpected size");
  }
  w.bytes(*signature);
  if (crypto.encrypts()) {
    auto cipher = crypto.encrypt(ByteSpan(out).subspan(start + header_size));
    if (!cipher.ok() || cipher->size() != secured_size) {
      out.resize(start);
      return cipher.ok() ? status_error(status::BadInternalError, "ciphertext of unexpected size")
                         : cipher.error();
    }
    out.resize(start + header_size);
    out.insert(out.end(), cipher->begin(), cipher->end());
  }
  return {};
}

Result<ByteSpan> open_chunk(ByteSpan chunk, std::size_t header_size, const MessageCrypto& crypto,
                            Bytes& scratch) {
  if (chunk.size() < header_size) {
    return status_error(status::BadDecodingError, "chunk shorter than its headers");
  }
  const std::size_t sig = crypto.signature_size();
  if (sig == 0 && !crypto.encrypts()) {
    return chunk.subspan(header_size);
  }
  ByteSpan plain = chunk.subspan(header_size);
  if (crypto.encrypts()) {
    if (plain.size() % crypto.cipher_block_size() != 0) {
      return status_error(status::BadSecurityChecksFailed, "encrypted part is not a whole number of blocks");
    }
    auto decrypted = crypto.decrypt(plain);
    if (!decrypted.ok()) {
      return decrypted.error();
    }
    // Verification needs the unencrypted headers followed by the plaintext.
    scratch.assign(chunk.begin(), chunk.begin() + static_cast<std::ptrdiff_t>(header_size));
    scratch.insert(scratch.end(), decrypted->begin(), decrypted->end());
  } else {
    scratch.assign(chunk.begin(), chunk.end());
  }
  if (scratch.size() < header_size + kSequenceHeaderSize + sig) {
    return status_error(status::BadSecurityChecksFailed, "chunk too short for its signature");
  }
  const std::size_t signed_size = scratch.size() - sig;
  SF_TRY(crypto.verify(ByteSpan(scratch).first(signed_size), ByteSpan(scratch).subspan(signed_size)));
  std::size_t end = signed_size;
  if (crypto.encrypts()) {
    const bool extra = crypto.extra_padding_byte();
    const std::size_t min_end = header_size + kSequenceHeaderSize + padding_field(0, extra);
    if (end < min_end) {
      return status_error(status::BadSecurityChecksFailed, "chunk too short for its padding");
    }
    std::size_t padding = scratch[end - 1];
    if (extra) {
      padding = (padding << 8U) | scratch[end - 2];
    }
    const std::size_t field = padding_field(padding, extra);
    if (end - (header_size + kSequenceHeaderSize) < field) {
      return status_error(status::BadSecurityChecksFailed, "padding longer than the chunk");
    }
    const std::size_t pad_start = end - field;
    const auto low = static_cast<std::uint8_t>(padding & 0xFFU);
    for (std::size_t i = pad_start; i < pad_start + 1 + padding; ++i) {
      if (scratch[i] != low) {
        return status_error(status::BadSecurityChecksFailed, "padding bytes do not match the padding size");
      }
    }
    end = pad_start;
  }
  return ByteSpan(scratch).subspan(header_size, end - header_size);
}

std::string reason_of(const Error& error) {
  // status_error put the code's name in front of the message; the reason is what follows.
  const std::string prefix = to_string(status_of(error)) + ": ";
  const std::string_view message = error.message;
  if (error.protocol_code && message.starts_with(prefix)) {
    return std::string(message.substr(prefix.size()));
  }
  return error.message;
}

bool is_request(const Message& message) {
  return std::visit(
      [](const auto& m) {
        return requires {
          m.request_header;
        };
      },
      message);
}

std::uint32_t request_handle_of(const Message& message) {
  return std::visit(
      [](const auto& m) -> std::uint32_t {
        if constexpr (requires { m.request_header; }) {
          return m.request_header.request_handle;
        } else {
          return m.response_header.request_handle;
        }
      },
      message);
}

}  // namespace sf::opcua::detail
