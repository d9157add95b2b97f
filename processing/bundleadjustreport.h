/***************************************************************************
  bundleadjustreport.h - the REPORT of geostation:bundle_adjust
 ***************************************************************************/
#ifndef BUNDLEADJUSTREPORT_H
#define BUNDLEADJUSTREPORT_H

#include <QJsonObject>
#include <QString>

#include "adjustment/bundleadjustment.h"

namespace GeoStationProcessing
{
  //! "tie", "control" or "check".
  QString bundlePointRoleName( geostation::BundlePointResult::Role role );

  /**
   * sigma0, redundancy, iterations; per image the adjusted orientation with
   * sigmas and its shift; the freed interior parameters with sigmas; control
   * and check points with their errors; every observation's residual
   * (projected - measured, px); the RMSEs (docs/conventions.md §9).
   */
  QJsonObject bundleAdjustReport( const geostation::BundleSummary &s );
}

#endif // BUNDLEADJUSTREPORT_H
