/***************************************************************************
  extractroadsreport.cpp - the REPORT of geostation:extract_roads
 ***************************************************************************/
#include "extractroadsreport.h"

#include <cmath>

#include <QJsonArray>
#include <QObject>

#include "extraction/resultmatrix.h"
#include "htmlreport.h"

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

  QByteArray extractRoadsHtml( const geostation::RoadNetworkSummary &s, const QString &leftId, const QString &rightId,
                               const std::vector<geostation::ControlPair> &control, int leftWidth, int leftHeight )
  {
    HtmlReport page( QObject::tr( "Roads extracted from %1 and %2" ).arg( leftId, rightId ) );
    double lengthPx = 0.0, lengthM = 0.0;
    for ( const geostation::CompiledPolygon &line : s.extraction.linesA )
      lengthPx += geostation::polylineLength( line.pixels );
    for ( const geostation::NetworkLine &line : s.network.lines )
      lengthM += line.lengthM();
    QVector<QPair<QString, QString>> summary { { QObject::tr( "pair" ), QStringLiteral( "%1, %2" ).arg( leftId, rightId ) },
      { QObject::tr( "mapping between the images" ), QString::fromStdString( s.mapping ) },
      { QObject::tr( "lines in the left image" ), QObject::tr( "%1 (%2 px)" ).arg( s.extraction.linesA.size() ).arg( number( lengthPx, 0 ) ) },
      { QObject::tr( "lines in the right image" ), QString::number( s.extraction.linesB.size() ) },
      { QObject::tr( "junctions in the left image" ), QString::number( s.extraction.intersectionsA.size() ) },
      { QObject::tr( "minimum contrast (grey levels)" ), number( s.minContrast, 1 ) + ( s.textureGrey > 0.0 ? QObject::tr( " (from the texture, %1)" ).arg( number( s.textureGrey, 1 ) ) : QString() ) },
      { QObject::tr( "time (s)" ), number( s.seconds, 1 ) } };
    if ( s.oriented )
    {
      summary << qMakePair( QObject::tr( "3-D lines" ), QObject::tr( "%1 (%2 m)" ).arg( s.network.lines.size() ).arg( number( lengthM, 0 ) ) );
      summary << qMakePair( QObject::tr( "mean terrain height (m)" ), number( s.meanHeightM, 2 ) +
                            ( s.terrainEstimate ? QObject::tr( " (matched, %1 points, spread %2 m)" ).arg( s.terrainEstimate->points ).arg( number( s.terrainEstimate->spreadM, 2 ) ) : QString() ) );
      if ( s.widthsFromMetres )
        summary << qMakePair( QObject::tr( "road widths (px)" ), QObject::tr( "%1 to %2 (ground pixel %3 m)" ).arg( number( s.widthsFromMetres->minPx, 1 ), number( s.widthsFromMetres->maxPx, 1 ),
                                                                                                            number( s.widthsFromMetres->groundPixelM, 3 ) ) );
    }
    page.keyValues( summary );
    if ( s.extraction.linesA.empty() )
      page.paragraph( QObject::tr( "No road was found in the pair." ) );

    page.heading( QObject::tr( "Rounds" ) );
    QVector<QStringList> rounds;
    for ( const geostation::RoundReport &r : s.extraction.rounds )
      rounds << QStringList { QString::number( r.round ), r.image == "A" ? QObject::tr( "left" ) : QObject::tr( "right" ), QString::number( r.startingPoints ), QString::number( r.linesStarted ),
                              QString::number( r.continued ), QString::number( r.polygons ), QString::number( r.wholly ), QString::number( r.partly ), QString::number( r.rejected ),
                              number( r.extractedPx, 0 ), number( r.acceptedPx, 0 ), number( r.seconds, 1 ) };
    page.table( { QObject::tr( "round" ), QObject::tr( "extracted in" ), QObject::tr( "starting points" ), QObject::tr( "lines started" ), QObject::tr( "continued" ), QObject::tr( "polygons" ),
                  QObject::tr( "accepted wholly" ), QObject::tr( "partly" ), QObject::tr( "rejected" ), QObject::tr( "extracted (px)" ), QObject::tr( "accepted (px)" ), QObject::tr( "time (s)" ) }, rounds );
    QVector<QStringList> stages;
    const auto stage = [&]( const QString &name, const geostation::StageCounts &c ) { stages << QStringList { name, number( c.seconds, 2 ), number( c.linePx, 0 ) }; };
    stage( QObject::tr( "starting points" ), s.extraction.startStage );
    stage( QObject::tr( "local extraction" ), s.extraction.lemStage );
    stage( QObject::tr( "regional extraction" ), s.extraction.remStage );
    stage( QObject::tr( "verification" ), s.extraction.verificationStage );
    stage( QObject::tr( "compilation" ), s.extraction.compilationStage );
    page.table( { QObject::tr( "stage" ), QObject::tr( "time (s)" ), QObject::tr( "line produced (px)" ) }, stages );

    page.heading( QObject::tr( "Lines" ) );
    QVector<QPolygonF> lines;
    for ( const geostation::CompiledPolygon &line : s.extraction.linesA )
    {
      QPolygonF polyline;
      for ( const Eigen::Vector2d &p : line.pixels )
        polyline << QPointF( p.x(), p.y() );
      lines << polyline;
    }
    page.linesPlot( QObject::tr( "The lines found in %1 (%2 x %3 px)." ).arg( leftId ).arg( leftWidth ).arg( leftHeight ), QSizeF( leftWidth, leftHeight ), lines );
    if ( s.oriented && !s.network.lines.empty() )
    {
      QVector<double> lengths, sigmas;
      for ( const geostation::NetworkLine &line : s.network.lines )
      {
        lengths << line.lengthM();
        for ( const geostation::NetworkVertex &v : line.vertices )
          sigmas << v.sigmaM.maxCoeff();
      }
      page.histogram( QObject::tr( "Lengths of the 3-D lines (m)." ), lengths, QStringLiteral( "m" ) );
      page.histogram( QObject::tr( "The 3-D vertices' largest coordinate sigma (m)." ), sigmas, QStringLiteral( "m" ) );
    }

    if ( s.registration )
    {
      page.heading( QObject::tr( "Registration by the control pairs" ) );
      page.keyValues( { { QObject::tr( "method" ), QString::fromStdString( s.registration->method ) }, { QObject::tr( "RMS (px)" ), number( s.registration->rmsPx, 2 ) },
                        { QObject::tr( "largest (px)" ), number( s.registration->maxPx, 2 ) }, { QObject::tr( "expected away from the points (px)" ), number( s.registration->expectedPx, 2 ) } } );
      QVector<QStringList> rows;
      QVector<double> residuals;
      for ( size_t i = 0; i < s.registration->residualsPx.size() && i < control.size(); ++i )
      {
        rows << QStringList { QString::fromStdString( control[i].id ), number( control[i].inA.x(), 1 ), number( control[i].inA.y(), 1 ), number( s.registration->residualsPx[i], 2 ) };
        residuals << s.registration->residualsPx[i];
      }
      page.table( { QObject::tr( "point" ), QObject::tr( "col (left)" ), QObject::tr( "row (left)" ), QObject::tr( "misregistration (px)" ) }, rows );
      page.histogram( QObject::tr( "Misregistration at the control pairs (pixels)." ), residuals, QStringLiteral( "px" ) );
    }
    return page.toUtf8();
  }
}
