#include "algorithms/estimate.h"

namespace grapebench {

const char* quantity_name(Quantity q) {
  switch (q) {
    case Quantity::Volume:
      return "volume";
    case Quantity::Height:
      return "height";
    case Quantity::Length:
      return "length";
    case Quantity::Width:
      return "width";
    case Quantity::PerimeterH:
      return "perimeter_h";
    case Quantity::PerimeterL:
      return "perimeter_l";
    case Quantity::PerimeterW:
      return "perimeter_w";
    case Quantity::SizeMajor:
      return "size_major";
    case Quantity::SizeMinor:
      return "size_minor";
    case Quantity::HangingHeight:
      return "hanging_height";
    case Quantity::MaxDiameter:
      return "max_diameter";
  }
  return "?";
}

std::vector<std::pair<std::string, Quantity>> quantity_choices() {
  std::vector<std::pair<std::string, Quantity>> out;
  for (Quantity q : kAllQuantities) out.emplace_back(quantity_name(q), q);
  return out;
}

}  // namespace grapebench
