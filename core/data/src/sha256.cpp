#include <cstdio>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <openssl/evp.h>

#include "rayspace/data_check.h"
#include "rayspace/error.h"

namespace rayspace::data {

std::string Sha256File(const std::filesystem::path& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) ThrowInput("{}: cannot read", path.string());
  std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> ctx(EVP_MD_CTX_new(), &EVP_MD_CTX_free);
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1) throw std::runtime_error("SHA-256: OpenSSL init failed");
  std::vector<unsigned char> block(1 << 20);
  for (std::size_t n; (n = std::fread(block.data(), 1, block.size(), f.get())) > 0;)
    if (EVP_DigestUpdate(ctx.get(), block.data(), n) != 1) throw std::runtime_error("SHA-256: OpenSSL update failed");
  if (std::ferror(f.get())) ThrowInput("{}: read error", path.string());
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  if (EVP_DigestFinal_ex(ctx.get(), digest, &len) != 1) throw std::runtime_error("SHA-256: OpenSSL final failed");
  std::string hex;
  for (unsigned int i = 0; i < len; ++i) hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

}  // namespace rayspace::data
