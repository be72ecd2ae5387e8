// The one-shot services of the client: Read and Write (OPC 10000-4 §5.10.2, §5.10.4), Browse and
// BrowseNext (§5.8.2, §5.8.3), TranslateBrowsePathsToNodeIds (§5.8.4), Call (§5.11.2) and
// GetEndpoints (§5.4.4). Operation-level results come back as the server sent them; the number
// of results must match the number of operations (§7.33 ResponseHeader / each service's table).
#include <memory>

#include "client_impl.hpp"

namespace sf::opcua {

namespace {

// Checks that a response has one result per operation.
template <typename T>
Result<std::vector<T>> per_operation(Array<T> results, std::size_t expected, std::string_view service,
                                     const log::Logger& logger) {
  if (results.size() != expected) {
    logger->warn("opcua client: {} returned {} results for {} operations", service, results.size(), expected);
    return status_error(status::BadUnknownResponse,
                        fmt::format("{}: {} results for {} operations", service, results.size(), expected));
  }
  return std::vector<T>(std::make_move_iterator(results.begin()), std::make_move_iterator(results.end()));
}

}  // namespace

void Client::Impl::read(std::vector<ReadValueId> nodes,
                        std::function<void(Result<std::vector<DataValue>>)> done) {
  if (auto error = check_connected("Read")) {
    fail_later(std::move(done), *error);
    return;
  }
  if (nodes.empty()) {
    fail_later(std::move(done), status_error(status::BadNothingToDo, "Read: no nodes"));
    return;
  }
  const std::size_t count = nodes.size();
  ReadRequest request;
  request.max_age = 0;
  request.timestamps_to_return = TimestampsToReturn::Both;
  request.nodes_to_read = std::move(nodes);
  send(std::move(request), [this, count, done = std::move(done)](Result<ReadResponse> response) {
    if (!response) {
      done(client_detail::error_of(response));
      return;
    }
    done(per_operation(std::move(response->results), count, "Read", logger));
  });
}

void Client::Impl::write(std::vector<WriteValue> nodes,
                         std::function<void(Result<std::vector<StatusCode>>)> done) {
  if (auto error = check_connected("Write")) {
    fail_later(std::move(done), *error);
    return;
  }
  if (nodes.empty()) {
    fail_later(std::move(done), status_error(status::BadNothingToDo, "Write: no nodes"));
    return;
  }
  const std::size_t count = nodes.size();
  WriteRequest request;
  request.nodes_to_write = std::move(nodes);
  send(std::move(request), [this, count, done = std::move(done)](Result<WriteResponse> response) {
    if (!response) {
      done(client_detail::error_of(response));
      return;
    }
    done(per_operation(std::move(response->results), count, "Write", logger));
  });
}

void Client::Impl::browse(BrowseDescription node,
                          std::function<void(Result<std::vector<ReferenceDescription>>)> done) {
  if (auto error = check_connected("Browse")) {
    fail_later(std::move(done), *error);
    return;
  }
  BrowseRequest request;
  request.requested_max_references_per_node = 0;  // the server's choice; BrowseNext fetches the rest
  request.nodes_to_browse.push_back(std::move(node));
  send(std::move(request), [this, done = std::move(done)](Result<BrowseResponse> response) mutable {
    if (!response) {
      done(client_detail::error_of(response));
      return;
    }
    auto results = per_operation(std::move(response->results), 1, "Browse", logger);
    if (!results) {
      done(client_detail::error_of(results));
      return;
    }
    BrowseResult& result = results->front();
    if (result.status_code.is_bad()) {
      done(status_error(result.status_code, "Browse"));
      return;
    }
    std::vector<ReferenceDescription> collected(std::make_move_iterator(result.references.begin()),
                                                std::make_move_iterator(result.references.end()));
    if (result.continuation_point.empty()) {
      done(std::move(collected));
      return;
    }
    browse_next(std::move(result.continuation_point), std::move(collected), std::move(done));
  });
}

void Client::Impl::browse_next(ByteString continuation_point, std::vector<ReferenceDescription> collected,
                               std::function<void(Result<std::vector<ReferenceDescription>>)> done) {
  if (auto error = check_connected("BrowseNext")) {
    done(*error);  // called from a response callback already
    return;
  }
  BrowseNextRequest request;
  request.release_continuation_points = false;
  request.continuation_points.push_back(std::move(continuation_point));
  send(std::move(request), [this, collected = std::move(collected),
                            done = std::move(done)](Result<BrowseNextResponse> response) mutable {
    if (!response) {
      done(client_detail::error_of(response));
      return;
    }
    auto results = per_operation(std::move(response->results), 1, "BrowseNext", logger);
    if (!results) {
      done(client_detail::error_of(results));
      return;
    }
    BrowseResult& result = results->front();
    if (result.status_code.is_bad()) {
      done(status_error(result.status_code, "BrowseNext"));
      return;
    }
    for (auto& reference : result.references) {
      collected.push_back(std::move(reference));
    }
    if (result.continuation_point.empty()) {
      done(std::move(collected));
      return;
    }
    browse_next(std::move(result.continuation_point), std::move(collected), std::move(done));
  });
}

void Client::Impl::translate(std::vector<BrowsePath> paths,
                             std::function<void(Result<std::vector<BrowsePathResult>>)> done) {
  if (auto error = check_connected("TranslateBrowsePathsToNodeIds")) {
    fail_later(std::move(done), *error);
    return;
  }
  if (paths.empty()) {
    fail_later(std::move(done),
               status_error(status::BadNothingToDo, "TranslateBrowsePathsToNodeIds: no paths"));
    return;
  }
  const std::size_t count = paths.size();
  TranslateBrowsePathsToNodeIdsRequest request;
  request.browse_paths = std::move(paths);
  send(std::move(request),
       [this, count, done = std::move(done)](Result<TranslateBrowsePathsToNodeIdsResponse> response) {
         if (!response) {
           done(client_detail::error_of(response));
           return;
         }
         done(per_operation(std::move(response->results), count, "TranslateBrowsePathsToNodeIds", logger));
       });
}

void Client::Impl::call(std::vector<CallMethodRequest> methods,
                        std::function<void(Result<std::vector<CallMethodResult>>)> done) {
  if (auto error = check_connected("Call")) {
    fail_later(std::move(done), *error);
    return;
  }
  if (methods.empty()) {
    fail_later(std::move(done), status_error(status::BadNothingToDo, "Call: no methods"));
    return;
  }
  const std::size_t count = methods.size();
  CallRequest request;
  request.methods_to_call = std::move(methods);
  send(std::move(request), [this, count, done = std::move(done)](Result<CallResponse> response) {
    if (!response) {
      done(client_detail::error_of(response));
      return;
    }
    done(per_operation(std::move(response->results), count, "Call", logger));
  });
}

// The discovery services need no session (OPC 10000-4 §5.4): on the session's channel when there
// is one, otherwise on a channel opened for this request and closed after it.
template <typename Response, typename Request>
void Client::Impl::discovery_request(Request request, std::function<void(Result<Response>)> finish) {
  if (channel && state == ClientState::Connected) {
    send(std::move(request), std::move(finish));
    return;
  }
  ClientTransportConfig transport;
  transport.endpoint_url = config.endpoint_url;
  transport.limits = config.limits;
  transport.connect_timeout = config.request_timeout;
  ClientChannel::open(
      loop, std::move(transport),
      [weak = weak_from_this(), request = std::move(request),
       finish = std::move(finish)](Result<std::shared_ptr<ClientChannel>> opened) mutable {
        auto self = weak.lock();
        if (!opened) {
          if (self && !self->shut_down) {
            finish(client_detail::error_of(opened));
          }
          return;
        }
        std::shared_ptr<ClientChannel> temporary = std::move(*opened);
        if (!self || self->shut_down) {
          temporary->close();
          return;
        }
        request.request_header = self->make_header(self->config.request_timeout);
        request.request_header.authentication_token = NodeId();
        temporary->send_request(
            Message(std::move(request)), self->config.request_timeout,
            [weak, temporary, finish = std::move(finish)](Result<Message> message) mutable {
              auto s = weak.lock();
              // Close after this callback returns, not from inside the channel.
              if (s) {
                s->loop.post([temporary]() { temporary->close(); });
              }
              if (!s || s->shut_down) {
                return;
              }
              finish(client_detail::unwrap_response<Response>(std::move(message), Request::kTypeName));
            });
      });
}

void Client::Impl::get_endpoints(std::function<void(Result<std::vector<EndpointDescription>>)> done) {
  GetEndpointsRequest request;
  request.endpoint_url = config.endpoint_url;
  discovery_request<GetEndpointsResponse>(std::move(request), [done](Result<GetEndpointsResponse> response) {
    if (!response) {
      done(client_detail::error_of(response));
      return;
    }
    done(std::vector<EndpointDescription>(std::make_move_iterator(response->endpoints.begin()),
                                          std::make_move_iterator(response->endpoints.end())));
  });
}

void Client::Impl::find_servers(std::vector<std::string> server_uris,
                                std::function<void(Result<std::vector<ApplicationDescription>>)> done) {
  FindServersRequest request;
  request.endpoint_url = config.endpoint_url;
  for (auto& uri : server_uris) {
    request.server_uris.push_back(String(std::move(uri)));
  }
  discovery_request<FindServersResponse>(std::move(request), [done](Result<FindServersResponse> response) {
    if (!response) {
      done(client_detail::error_of(response));
      return;
    }
    done(std::vector<ApplicationDescription>(std::make_move_iterator(response->servers.begin()),
                                             std::make_move_iterator(response->servers.end())));
  });
}

}  // namespace sf::opcua
