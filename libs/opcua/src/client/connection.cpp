// Losing and re-establishing the connection (OPC 10000-4 §6.7): drop the channel, retry with
// exponential backoff, keep the session alive and notice half-open connections; and the two
// ways out: disconnect() (CloseSession, §5.6.4) and the destructor's shutdown().
#include <algorithm>

#include "client_impl.hpp"

namespace sf::opcua {

void Client::Impl::lose_channel(std::uint64_t generation, const Error& error) {
  if (generation != channel_generation || shut_down) {
    return;
  }
  drop_channel();
  if (disconnecting) {
    return;  // disconnect() finishes on its own
  }
  switch (state) {
    case ClientState::Connecting: {
      forget_session();
      set_state(ClientState::Disconnected, error);
      if (auto done = std::exchange(connect_done, nullptr)) {
        done(error);
      }
      break;
    }
    case ClientState::Connected:
    case ClientState::Reconnecting:
      if (config.auto_reconnect) {
        set_state(ClientState::Reconnecting, error);
        schedule_reconnect();
      } else {
        forget_session();
        subscriptions.clear();
        set_state(ClientState::Disconnected, error);
      }
      break;
    case ClientState::Disconnected:
      break;
  }
}

void Client::Impl::drop_channel() {
  ++channel_generation;
  stop_timers();
  publish_outstanding = 0;
  if (session) {
    session->activated = false;
  }
  if (channel) {
    auto old = std::move(channel);
    channel.reset();
    old->set_on_closed(nullptr);
    // Not from inside the channel's own callback: close on the next loop iteration.
    loop.post([old]() { old->close(); });
  }
}

void Client::Impl::schedule_reconnect() {
  if (reconnect_timer != 0) {
    return;
  }
  const auto delay = backoff;
  backoff = std::min(backoff * 2, config.reconnect_max);
  logger->info("opcua client {}: reconnecting in {} ms", config.endpoint_url, delay.count());
  reconnect_timer = loop.add_timer(delay, [weak = weak_from_this()]() {
    auto self = weak.lock();
    if (!self || self->shut_down) {
      return;
    }
    self->reconnect_timer = 0;
    if (self->state == ClientState::Reconnecting && !self->channel) {
      self->open_channel();
    }
  });
}

// Without traffic the server closes the session after its timeout, and a half-open TCP
// connection would go unnoticed: read the server's CurrentTime (i=2258) at a third of the
// session timeout; a timeout on it counts as a lost channel.
void Client::Impl::start_keep_alive() {
  if (keep_alive_timer != 0) {
    loop.cancel_timer(keep_alive_timer);
  }
  const double timeout_ms =
      session && session->revised_timeout_ms > 0 ? session->revised_timeout_ms : 30'000.0;
  const auto interval =
      std::chrono::milliseconds(static_cast<std::int64_t>(std::clamp(timeout_ms / 3, 500.0, 30'000.0)));
  keep_alive_timer = loop.add_periodic(interval, [weak = weak_from_this()]() {
    auto self = weak.lock();
    if (!self || self->shut_down || self->check_connected("keep-alive")) {
      return;
    }
    ReadRequest request;
    request.timestamps_to_return = TimestampsToReturn::Neither;
    request.nodes_to_read.push_back(value_of(NodeId(0, id::Server_ServerStatus_CurrentTime)));
    const std::uint64_t generation = self->channel_generation;
    self->send(std::move(request), [weak, generation](Result<ReadResponse> response) {
      auto s = weak.lock();
      if (s && !response && client_detail::is_transport_error(status_of(response.error()))) {
        s->logger->warn("opcua client {}: keep-alive failed: {}", s->config.endpoint_url,
                        response.error().message);
        s->lose_channel(generation, response.error());
      }
    });
  });
}

void Client::Impl::stop_timers() {
  for (auto* timer : {&keep_alive_timer, &publish_retry_timer}) {
    if (*timer != 0) {
      loop.cancel_timer(*timer);
      *timer = 0;
    }
  }
}

void Client::Impl::forget_session() {
  session.reset();
  pending_acks.clear();
  for (auto& [id, sub] : subscriptions) {
    sub.server_id = 0;
  }
}

void Client::Impl::disconnect(std::function<void()> done) {
  if (reconnect_timer != 0) {
    loop.cancel_timer(reconnect_timer);
    reconnect_timer = 0;
  }
  if (state == ClientState::Disconnected || disconnecting) {
    post(std::move(done));
    return;
  }
  if (auto pending = std::exchange(connect_done, nullptr)) {
    post([pending]() {
      pending(status_error(status::BadRequestInterrupted, "connect: disconnect() was called"));
    });
  }
  disconnecting = true;
  auto finish = [this, done = std::move(done)]() {
    drop_channel();
    forget_session();
    subscriptions.clear();
    disconnecting = false;
    set_state(ClientState::Disconnected, {});
    done();
  };
  if (channel && session && session->activated) {
    CloseSessionRequest request;
    request.delete_subscriptions = true;
    send(std::move(request), [this, finish = std::move(finish)](Result<CloseSessionResponse> response) {
      if (!response) {
        logger->info("opcua client {}: CloseSession: {}", config.endpoint_url, response.error().message);
      }
      finish();
    });
    return;
  }
  post(std::move(finish));
}

void Client::Impl::shutdown() {
  if (shut_down) {
    return;
  }
  on_state = nullptr;
  connect_done = nullptr;
  stop_timers();
  if (reconnect_timer != 0) {
    loop.cancel_timer(reconnect_timer);
    reconnect_timer = 0;
  }
  if (channel && session && session->activated) {
    // Best effort: the request goes out before the CLO; nobody waits for the answer.
    CloseSessionRequest request;
    request.delete_subscriptions = true;
    request.request_header = make_header(config.request_timeout);
    channel->send_request(Message(std::move(request)), config.request_timeout, [](Result<Message>) {});
  }
  shut_down = true;
  ++channel_generation;
  if (channel) {
    auto old = std::move(channel);
    channel.reset();
    old->set_on_closed(nullptr);
    loop.post([old]() { old->close(); });
  }
  subscriptions.clear();
  session.reset();
}

}  // namespace sf::opcua
