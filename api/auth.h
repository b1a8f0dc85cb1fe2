// Authorizer: who may do what (api.md, "Auth"). Without configured tokens
// only loopback clients are served, without tokens. With tokens, every
// request but /healthz and /readyz needs `Authorization: Bearer <token>`:
//   machine      writes temperatures and probe points of its own machine,
//                reads its own machine and compensation
//   reader       reads everything
//   maintenance  reads everything (and will request checks)
//   admin        everything
#pragma once

#include <string>
#include <vector>

#include "server/config.h"

namespace thermocomp::api {

struct AuthDecision {
  int status = 200;    // 200 allowed, 401 no/unknown token, 403 not permitted
  std::string reason;  // why not, for the problem detail
  std::string actor;   // who, for the audit
};

class Authorizer {
 public:
  explicit Authorizer(std::vector<AccessToken> tokens) : tokens_(std::move(tokens)) {}
  AuthDecision Decide(const std::string& method, const std::string& path,
                      const std::string& remote_addr, const std::string& authorization) const;

 private:
  std::vector<AccessToken> tokens_;
};

bool IsLoopback(const std::string& addr);

}  // namespace thermocomp::api
