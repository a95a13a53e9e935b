#include "d2vdb/field/detail/DomainError.h"

#include <cmath>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb::detail {

void throwOutsideDomain(const Eigen::Vector3d& point, const Eigen::AlignedBox3d& domain,
                        const std::string& what, int pointDigits) {
  std::ostringstream message;
  message.precision(6);
  message << "the point " << formatPoint(point, pointDigits) << " lies "
          << std::sqrt(domain.squaredExteriorDistance(point))
          << " outside the working domain of the " << what << " (box "
          << formatPoint(domain.min(), pointDigits) << " to "
          << formatPoint(domain.max(), pointDigits) << ")";
  throw InputError(message.str());
}

}  // namespace d2vdb::detail
