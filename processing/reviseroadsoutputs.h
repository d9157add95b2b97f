/***************************************************************************
  reviseroadsoutputs.h - the tables and REPORT of geostation:revise_roads
  -------------------------------------------------------------------------
  What each row of OUTPUT, VERTICES and NEW holds, built from core's
  MapRevisionSummary; the algorithm only opens the sinks and adds them.
 ***************************************************************************/
#ifndef REVISEROADSOUTPUTS_H
#define REVISEROADSOUTPUTS_H

#include <QJsonObject>
#include <QList>
#include <QString>

#include <qgsfeature.h>
#include <qgsfields.h>

#include "revision/maprevision.h"

namespace GeoStationProcessing
{
  //! OUTPUT's fields: the map's own but its fid (a split feature would repeat it), then the eight the revision adds.
  struct RevisedMapFields
  {
    QgsFields fields;
    QList<int> copied; //!< the map's field indices, in order
  };

  //! Throws QgsProcessingException when the map already has a field the output adds.
  RevisedMapFields revisedMapFields( const QgsFields &mapFields );

  /**
   * One OUTPUT row: the source feature's attributes, its id, status,
   * evidence, shift, sigma, the part of the feature (`part`) and where the
   * piece lies along it; no geometry for invalid_geometry.
   */
  QgsFeature revisedMapFeature( const geostation::RevisedPiece &piece, const QgsFeature &source, int part, const RevisedMapFields &fields );

  //! VERTICES' fields: piece (the OUTPUT row, from 1), vertex, X, Y, Z, sx, sy, sz, height_from, map_m.
  QgsFields revisionVertexFields();
  //! The measured vertices of one piece (none where the map's course is kept).
  QList<QgsFeature> revisionVertexRows( const geostation::RevisedPiece &piece, int pieceNumber, const QgsFields &fields );

  //! NEW's fields: line_id, method, length_m, sigma_max.
  QgsFields newRoadFields();
  QgsFeature newRoadFeature( const geostation::NetworkLine &line, int lineId, const QgsFields &fields );

  //! Length and count per status, the new roads, what the map decided against what extraction found, and the run's scale.
  QJsonObject reviseRoadsReport( const geostation::MapRevisionSummary &s, const QString &leftId, const QString &rightId, long long mapFeatures );
}

#endif // REVISEROADSOUTPUTS_H
