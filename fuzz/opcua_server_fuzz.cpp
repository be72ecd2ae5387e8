// The server's message path on arbitrary input (OPC 10000-6 §6.7.1, the message body after the
// secure channel layer): the bytes are decoded as a service message exactly as the transport
// does, and when they decode, the request is run through the Dispatcher — with the session
// token of an open, activated session patched in, so the fuzzer reaches every service (Read,
// Write, Browse, Call, subscriptions, Publish) and not only the session check.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>

#include "sf/examples/opcua_demo.hpp"
#include "sf/opcua/server/dispatcher.hpp"
#include "sf/opcua/server/ns0.hpp"

namespace {

using namespace sf::opcua;
using namespace sf::opcua::server;

class NullChannel final : public ServerChannel {
 public:
  NullChannel() { info_.channel_id = 1; }
  [[nodiscard]] const ChannelInfo& info() const override { return info_; }
  void send_response(std::uint32_t, const Message& response) override {
    // Every response must encode (the transport would send it).
    (void)encode_message(response);
  }
  void close() override {}
  [[nodiscard]] bool is_open() const override { return true; }

 private:
  ChannelInfo info_;
};

struct World {
  sf::ManualClock clock;
  AddressSpace space;
  std::unique_ptr<Dispatcher> dispatcher;
  std::shared_ptr<NullChannel> channel = std::make_shared<NullChannel>();
  NodeId token;

  World() {
    (void)build_namespace0(space);
    space.add_namespace("urn:smartfactory:fuzz");
    (void)sf::examples::add_demo_nodes(space);
    dispatcher = std::make_unique<Dispatcher>(space, clock, ServerIdentity{}, SessionLimits{},
                                              SubscriptionLimits{}, OperationLimits{});
  }

  // A fresh session per input keeps runs independent of each other's subscriptions.
  void open_session() {
    struct Capture final : ServerChannel {
      ChannelInfo info_{1, {}, {}, {}, MessageSecurityMode::None, {}};
      Message last;
      [[nodiscard]] const ChannelInfo& info() const override { return info_; }
      void send_response(std::uint32_t, const Message& response) override { last = response; }
      void close() override {}
      [[nodiscard]] bool is_open() const override { return true; }
    };
    auto capture = std::make_shared<Capture>();
    CreateSessionRequest create;
    dispatcher->on_request(capture, 1, create);
    token = std::get<CreateSessionResponse>(capture->last).authentication_token;
    ActivateSessionRequest activate;
    activate.request_header.authentication_token = token;
    dispatcher->on_request(capture, 2, activate);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static World world;
  auto message = decode_message(sf::ByteSpan(data, size));
  if (!message) {
    return 0;
  }
  world.open_session();
  std::visit(
      [&](auto& request) {
        if constexpr (requires { request.request_header; }) {
          // Keep a null token as the fuzzer wrote it half of the time, to fuzz the checks too.
          if (size % 2 == 0) {
            request.request_header.authentication_token = world.token;
          }
        }
      },
      *message);
  world.dispatcher->on_request(world.channel, 3, std::move(*message));
  world.clock.advance(std::chrono::milliseconds(100));
  world.dispatcher->tick();
  CloseSessionRequest close;
  close.request_header.authentication_token = world.token;
  close.delete_subscriptions = true;
  world.dispatcher->on_request(world.channel, 4, close);
  return 0;
}
