/***************************************************************************
  extractroadsreport.h - the REPORT of geostation:extract_roads
 ***************************************************************************/
#ifndef EXTRACTROADSREPORT_H
#define EXTRACTROADSREPORT_H

#include <vector>

#include <QByteArray>
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

  /**
   * The same for reading: the summary, the rounds and stages, the lines
   * drawn over the left image's frame, a histogram of the 3-D lines'
   * lengths and of their vertices' largest sigma, and the registration's
   * misregistration per control pair.
   */
  QByteArray extractRoadsHtml( const geostation::RoadNetworkSummary &s, const QString &leftId, const QString &rightId,
                               const std::vector<geostation::ControlPair> &control, int leftWidth, int leftHeight );
}

#endif // EXTRACTROADSREPORT_H
