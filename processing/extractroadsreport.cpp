/***************************************************************************
  extractroadsreport.cpp - the REPORT of geostation:extract_roads
 ***************************************************************************/
#include "extractroadsreport.h"

#include <cmath>

#include <QJsonArray>

namespace GeoStationProcessing
{
  QJsonObject extractRoadsReport( const geostation::RoadNetworkSummary &s, const QString &leftId, const QString &rightId,
                                  const std::vector<geostation::ControlPair> &control )
  {
    QJsonArray rounds;
    for ( const geostation::RoundReport &r : s.extraction.rounds )
      rounds.append( QJsonObject { { "round", r.round }, { "extracted_in", r.image == "A" ? "left" : "right" }, { "starting_points", r.startingPoints },
        { "lines_started", r.linesStarted }, { "continued_from_dead_ends", r.continued }, { "polygons", r.polygons }, { "accepted_wholly", r.wholly },
        { "accepted_partly", r.partly }, { "rejected", r.rejected }, { "extracted_px", r.extractedPx }, { "accepted_px", r.acceptedPx }, { "seconds", r.seconds } } );
    const auto stage = []( const geostation::StageCounts &c ) { return QJsonObject { { "seconds", c.seconds }, { "line_px", c.linePx }, { "image_px", static_cast<double>( c.imagePixels ) } }; };
    QJsonObject report { { "algorithm", "geostation:extract_roads" }, { "left", leftId }, { "right", rightId },
      { "mapping", QString::fromStdString( s.mapping ) }, { "rounds", rounds }, { "lines_left", static_cast<int>( s.extraction.linesA.size() ) },
      { "lines_right", static_cast<int>( s.extraction.linesB.size() ) }, { "intersections_left", static_cast<int>( s.extraction.intersectionsA.size() ) },
      { "intersections_right", static_cast<int>( s.extraction.intersectionsB.size() ) }, { "gaps_bridged", s.extraction.bridged },
      { "stages", QJsonObject { { "starting_points", stage( s.extraction.startStage ) }, { "lem", stage( s.extraction.lemStage ) }, { "rem", stage( s.extraction.remStage ) },
          { "verification", stage( s.extraction.verificationStage ) }, { "compilation", stage( s.extraction.compilationStage ) } } },
      { "seconds", s.seconds }, { "empty", s.extraction.linesA.empty() }, { "min_contrast", s.minContrast }, { "texture_grey", s.textureGrey }, { "verification_search_px", s.verificationSearchPx },
      { "reading", QJsonObject { { "in_windows", s.reading.inWindows }, { "sub_images", s.extraction.subImages },
          { "temporary_dead_ends", s.extraction.temporaryDeadEnds }, { "grey_tiles_read", static_cast<double>( s.reading.greyTilesRead ) },
          { "matching_windows", static_cast<double>( s.reading.matchingWindows ) }, { "peak_matching_mb", s.reading.peakMatchingBytes / 1048576.0 } } } };
    if ( s.oriented )
    {
      report.insert( "mean_height_m", s.meanHeightM );
      if ( s.terrainEstimate )
        report.insert( "terrain_estimate", QJsonObject { { "height_m", s.terrainEstimate->heightM }, { "points", s.terrainEstimate->points }, { "spread_m", s.terrainEstimate->spreadM },
                                                         { "voting_points", s.terrainEstimate->votingPoints }, { "by_least_squares", s.terrainEstimate->byLeastSquares } } );
      if ( s.widthsFromMetres )
        report.insert( "road_widths", QJsonObject { { "ground_pixel_m", s.widthsFromMetres->groundPixelM }, { "min_px", s.widthsFromMetres->minPx },
                                                    { "max_px", s.widthsFromMetres->maxPx }, { "clamped", s.widthsFromMetres->clamped } } );
      report.insert( "vertices_3d", QJsonObject { { "total", s.network.vertices }, { "by_line_crossing", s.network.byCrossing }, { "by_area_matching", s.network.byArea },
        { "unmatched", s.network.unmatched } } );
    }
    if ( s.registration )
    {
      QJsonArray residuals;
      for ( size_t i = 0; i < s.registration->residualsPx.size(); ++i )
        residuals.append( QJsonObject { { "point_id", QString::fromStdString( control[i].id ) }, { "misregistration_px", s.registration->residualsPx[i] } } );
      report.insert( "registration", QJsonObject { { "method", QString::fromStdString( s.registration->method ) }, { "rms_px", s.registration->rmsPx },
        { "max_px", s.registration->maxPx }, { "expected_px", std::isfinite( s.registration->expectedPx ) ? QJsonValue( s.registration->expectedPx ) : QJsonValue() },
        { "points", residuals } } );
    }
    return report;
  }
}
