// The worst-conformant device's arithmetic (docs/simulator.md, "Device models"): every float
// operation Vulkan lets a device round loosely takes a value other than the correctly rounded one,
// still inside the bound the Vulkan environment for SPIR-V sets, so a kernel that silently relies on
// lavapipe's IEEE arithmetic gives other bits here. Values are bit patterns of one component
// (`width` 32 or 64), as the executor holds them.
//
// The choices, each one a real device's or the bound's edge:
// - +, -, *, conversions to float: rounded toward zero (a rounding mode the kernels do not exclude);
//   a finite result that overflows stays at the largest finite value, as toward-zero rounding does
//   (or, in the worst-nearest model, to nearest as every desktop GPU does by default);
// - /: the correctly rounded quotient moved by 1 or 2 ULP (the bound is 2.5 ULP);
// - inversesqrt: moved by 1 ULP (bound 2 ULP); sqrt: 1 / inversesqrt with both loose, the bound it
//   inherits;
// - double operations carry single precision ("at least that of single precision"): the result is
//   rounded toward zero to 24 significant bits, and / and sqrt move by 1 or 2 of those ULP;
// - min and max with one NaN operand return the NaN (either is allowed);
// - denormal operands and results flush to zero with their sign (no DenormPreserve is declared).
// Which way and how far is drawn from a hash of the seed, the operation and its operands: the same
// operands give the same result wherever and whenever they are computed, as on a real device.
#pragma once
#include <cstdint>

namespace rayspace::sim {

enum class FloatOpKind : std::uint8_t { kAdd, kSub, kMul, kDiv, kSqrt, kInverseSqrt, kMin, kMax, kFused };

class DeviceMath {
 public:
  // toward_zero false: +, -, * and conversions round to nearest (the worst-nearest model), the rest
  // as above.
  explicit DeviceMath(std::uint64_t seed, bool toward_zero = true) : seed_(seed), toward_zero_(toward_zero) {}
  // a op b (kSqrt, kInverseSqrt: of a).
  std::uint64_t Binary(FloatOpKind op, std::uint32_t width, std::uint64_t a, std::uint64_t b) const;
  // a * b + c in one rounding: a multiply and an add the device contracted (neither NoContraction).
  std::uint64_t Fused(std::uint32_t width, std::uint64_t a, std::uint64_t b, std::uint64_t c) const;
  // A conversion to a float of `width` bits from a double (a narrowing or a float-to-double
  // widening) or from an integer: rounded toward zero.
  std::uint64_t FromDouble(std::uint32_t width, double v) const;
  std::uint64_t FromInteger(std::uint32_t width, std::uint64_t magnitude, bool negative) const;

 private:
  std::uint64_t Draw(FloatOpKind op, std::uint64_t a, std::uint64_t b) const;
  std::uint64_t seed_;
  bool toward_zero_;
};

}  // namespace rayspace::sim
