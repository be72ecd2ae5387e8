#include "sf/web/server.hpp"

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/strand.hpp>
#include <thread>

#include "http_session.hpp"
#include "live_session.hpp"
#include "sf/core/log.hpp"
#include "tls.hpp"

namespace sf::web {
namespace net = boost::asio;
using tcp = net::ip::tcp;

class HttpServer::Impl {
 public:
  Impl(ServerConfig config, Router router) : state_(std::make_shared<ServerState>()) {
    state_->config = std::move(config);
    state_->router = std::move(router);
    state_->hub = std::make_shared<LiveHub>();
  }

  Result<std::uint16_t> start() {
    if (context_) {
      return Error(Errc::state, "server already started");
    }
    state_->tls.reset();
    if (state_->config.tls) {
      auto tls = make_tls_context(*state_->config.tls);
      if (!tls) {
        return tls.error();
      }
      state_->tls = std::move(*tls);
    }
    auto context = std::make_unique<net::io_context>(std::max(1, state_->config.threads));
    auto acceptor = std::make_shared<tcp::acceptor>(*context);
    beast::error_code error;
    const auto address = net::ip::make_address(state_->config.host, error);
    if (error) {
      return Error(Errc::invalid_argument, "http host " + state_->config.host + ": " + error.message());
    }
    const tcp::endpoint endpoint(address, state_->config.port);
    acceptor->open(endpoint.protocol(), error);
    if (!error) {
      acceptor->set_option(net::socket_base::reuse_address(true), error);
    }
    if (!error) {
      acceptor->bind(endpoint, error);
    }
    if (!error) {
      acceptor->listen(net::socket_base::max_listen_connections, error);
    }
    if (error) {
      return Error(Errc::io, "http listen on " + state_->config.host + ":" +
                                 std::to_string(state_->config.port) + ": " + error.message());
    }
    const auto port = acceptor->local_endpoint().port();
    context_ = std::move(context);
    acceptor_ = acceptor;
    accept_next();
    for (int i = 0; i < std::max(1, state_->config.threads); ++i) {
      threads_.emplace_back([this] { context_->run(); });
    }
    sf::log::get("web")->info("{} listening on {}:{}", state_->tls ? "https" : "http", state_->config.host,
                              port);
    return port;
  }

  void stop() {
    if (!context_) {
      return;
    }
    net::post(*context_, [acceptor = acceptor_] {
      beast::error_code ignored;
      acceptor->close(ignored);
    });
    context_->stop();
    for (auto& thread : threads_) {
      thread.join();
    }
    threads_.clear();
    acceptor_.reset();
    // Destroying the context destroys every pending handler and with them the connections.
    context_.reset();
  }

  void publish(const std::string& topic, const nlohmann::json& value) { state_->hub->publish(topic, value); }

  ServerStats stats() const {
    ServerStats stats;
    stats.connections = state_->connections.load();
    stats.requests = state_->requests.load();
    stats.refused_connections = state_->refused.load();
    stats.tls_failures = state_->tls_failures.load();
    stats.live_clients = state_->hub->stats();
    return stats;
  }

 private:
  void accept_next() {
    acceptor_->async_accept(
        net::make_strand(*context_),
        [this, acceptor = acceptor_](const beast::error_code& error, tcp::socket socket) {
          if (error == net::error::operation_aborted || !acceptor->is_open()) {
            return;
          }
          if (!error) {
            std::shared_ptr<ConnectionSlot> slot;
            if (state_->connections.load() < state_->config.max_connections) {
              slot = std::make_shared<ConnectionSlot>(state_->connections);
            } else {
              ++state_->refused;
            }
            std::make_shared<HttpSession>(std::move(socket), state_, std::move(slot))->run();
          }
          accept_next();
        });
  }

  std::shared_ptr<ServerState> state_;
  std::unique_ptr<net::io_context> context_;
  std::shared_ptr<tcp::acceptor> acceptor_;
  std::vector<std::thread> threads_;
};

HttpServer::HttpServer(ServerConfig config, Router router)
    : impl_(std::make_unique<Impl>(std::move(config), std::move(router))) {}
HttpServer::~HttpServer() {
  stop();
}
Result<std::uint16_t> HttpServer::start() {
  return impl_->start();
}
void HttpServer::stop() {
  impl_->stop();
}
void HttpServer::publish(const std::string& topic, const nlohmann::json& value) {
  impl_->publish(topic, value);
}
ServerStats HttpServer::stats() const {
  return impl_->stats();
}

}  // namespace sf::web
