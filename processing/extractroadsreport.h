/***************************************************************************
  extractroadsreport.h - the REPORT of geostation:extract_roads
 ***************************************************************************/
#ifndef EXTRACTROADSREPORT_H
#define EXTRACTROADSREPORT_H

#include <vector>

#include <QJsonObject>
#include <QString>

#include "extraction/roadnetworkextractor.h"

namespace GeoStationProcessing
{
  /**
   * The rounds (extracted, accepted, rejected per round), line and
   * intersection counts, the time per stage, how the pair was read (in
   * windows: sub-images, lines continued across their borders, tiles and
   * matching windows read), the 3-D vertices of an oriented pair, and the
   * registration's misregistration per control pair.
   */
  QJsonObject extractRoadsReport( const geostation::RoadNetworkSummary &s, const QString &leftId, const QString &rightId,
                                  const std::vector<geostation::ControlPair> &control );
}

#endif // EXTRACTROADSREPORT_H
