/***************************************************************************
  orientationreports.cpp - the HTML reports of the orienting algorithms
 ***************************************************************************/
#include "orientationreports.h"

#include <algorithm>
#include <cmath>

#include <QObject>

#include <Eigen/LU>

#include "bundleadjustreport.h"
#include "htmlreport.h"

namespace GeoStationProcessing
{
  namespace
  {
    constexpr int kMostPlots = 12;
    constexpr int kMostResidualRows = 20;

    QString text( const std::string &s )
    {
      return QString::fromStdString( s );
    }

    QString joined( const std::vector<std::string> &ids )
    {
      QStringList out;
      for ( const std::string &id : ids )
        out << text( id );
      return out.join( QStringLiteral( ", " ) );
    }

    QString yesNo( bool value )
    {
      return value ? QObject::tr( "yes" ) : QObject::tr( "no" );
    }

    QString valueWithSigma( double value, const std::optional<double> &sigma, int decimals )
    {
      return sigma ? QStringLiteral( "%1 ± %2" ).arg( number( value, decimals ), number( *sigma, decimals ) ) : number( value, decimals );
    }

    QString unitOfParameter( const std::string &name )
    {
      if ( name == "X0" || name == "Y0" || name == "Z0" )
        return QStringLiteral( "m" );
      if ( name == "omega" || name == "phi" || name == "kappa" )
        return QStringLiteral( "deg" );
      if ( name == "f" || name == "cx" || name == "cy" )
        return QStringLiteral( "px" );
      return QString();
    }

    QVector<QStringList> parameterRows( const std::vector<std::string> &names, const std::vector<double> &estimates, const std::vector<double> &sigmas )
    {
      QVector<QStringList> rows;
      for ( size_t i = 0; i < names.size() && i < estimates.size() && i < sigmas.size(); ++i )
      {
        const bool angle = unitOfParameter( names[i] ) == QLatin1String( "deg" );
        const bool coefficient = unitOfParameter( names[i] ).isEmpty();
        const int decimals = coefficient ? 8 : angle ? 5 : 3;
        rows << QStringList { text( names[i] ), number( estimates[i], decimals ), number( sigmas[i], decimals ), unitOfParameter( names[i] ) };
      }
      return rows;
    }

    QVector<double> lengths( const QVector<ResidualArrow> &arrows )
    {
      QVector<double> out;
      for ( const ResidualArrow &a : arrows )
        out << std::hypot( a.residual.x(), a.residual.y() );
      return out;
    }

    QString residualLabel( const QString &id, const Eigen::Vector2d &residualPx )
    {
      return QStringLiteral( "%1: %2, %3 px" ).arg( id, number( residualPx.x(), 2 ), number( residualPx.y(), 2 ) );
    }
  } // namespace

  QByteArray bundleAdjustHtml( const geostation::BundleSummary &s, const geostation::Block &block )
  {
    HtmlReport page( QObject::tr( "Bundle adjustment" ) );
    page.keyValues( { { QObject::tr( "sigma0" ), number( s.sigma0, 3 ) }, { QObject::tr( "redundancy" ), QString::number( s.redundancy ) },
                      { QObject::tr( "iterations" ), QString::number( s.iterations ) }, { QObject::tr( "converged" ), yesNo( s.converged ) },
                      { QObject::tr( "residual RMS (px)" ), number( s.rmsPx, 3 ) }, { QObject::tr( "observations" ), QString::number( s.observations.size() ) },
                      { QObject::tr( "control points" ), QString::number( s.controlCount ) }, { QObject::tr( "check points" ), QString::number( s.checkCount ) },
                      { QObject::tr( "RMSE on control X, Y, Z (m)" ), s.controlCount ? QStringLiteral( "%1, %2, %3" ).arg( number( s.rmseControlM.x(), 3 ), number( s.rmseControlM.y(), 3 ), number( s.rmseControlM.z(), 3 ) ) : QStringLiteral( "-" ) },
                      { QObject::tr( "RMSE on check X, Y, Z (m)" ), s.checkCount ? QStringLiteral( "%1, %2, %3" ).arg( number( s.rmseCheckM.x(), 3 ), number( s.rmseCheckM.y(), 3 ), number( s.rmseCheckM.z(), 3 ) ) : QStringLiteral( "-" ) },
                      { QObject::tr( "solve (s)" ), number( s.solveSeconds, 2 ) } } );
    if ( !s.skippedPoints.empty() )
      page.paragraph( QObject::tr( "%1 points were seen in fewer than two images and left out." ).arg( s.skippedPoints.size() ) );

    page.heading( QObject::tr( "Images" ) );
    QVector<QStringList> imageRows;
    for ( const geostation::BundleImageResult &i : s.images )
    {
      if ( i.observationCount == 0 )
        continue;
      const geostation::ExteriorOrientation &e = i.exterior;
      const auto sigma = [&]( double geostation::ExteriorSigma::*m ) { return e.sigma ? std::optional<double>( ( *e.sigma ).*m ) : std::nullopt; };
      imageRows << QStringList { text( i.id ), QString::number( i.observationCount ), number( i.rmsPx, 3 ), valueWithSigma( e.projectionCentre.x(), sigma( &geostation::ExteriorSigma::x ), 3 ),
                                 valueWithSigma( e.projectionCentre.y(), sigma( &geostation::ExteriorSigma::y ), 3 ), valueWithSigma( e.projectionCentre.z(), sigma( &geostation::ExteriorSigma::z ), 3 ),
                                 valueWithSigma( e.omegaDeg, sigma( &geostation::ExteriorSigma::omegaDeg ), 4 ), valueWithSigma( e.phiDeg, sigma( &geostation::ExteriorSigma::phiDeg ), 4 ),
                                 valueWithSigma( e.kappaDeg, sigma( &geostation::ExteriorSigma::kappaDeg ), 4 ), number( i.shiftM.norm(), 3 ) };
    }
    page.table( { QObject::tr( "image" ), QObject::tr( "observations" ), QObject::tr( "RMS (px)" ), QStringLiteral( "X (m)" ), QStringLiteral( "Y (m)" ), QStringLiteral( "Z (m)" ),
                  QObject::tr( "omega (deg)" ), QObject::tr( "phi (deg)" ), QObject::tr( "kappa (deg)" ), QObject::tr( "shift (m)" ) }, imageRows );

    QVector<QStringList> cameraRows;
    for ( const geostation::BundleCameraResult &c : s.cameras )
    {
      double values[geostation::kInteriorSize];
      geostation::interiorBlockFromCamera( c.camera, values );
      for ( size_t k = 0; k < c.freeParameters.size(); ++k )
        cameraRows << QStringList { text( c.camera.id ), text( c.freeParameters[k] ), number( values[*geostation::interiorParameterIndex( c.freeParameters[k] )], 6 ), number( c.sigmas[k], 6 ) };
    }
    if ( !cameraRows.isEmpty() )
    {
      page.heading( QObject::tr( "Interior parameters estimated" ) );
      page.table( { QObject::tr( "camera" ), QObject::tr( "parameter" ), QObject::tr( "value" ), QObject::tr( "sigma" ) }, cameraRows );
    }

    QVector<QStringList> pointRows;
    for ( const geostation::BundlePointResult &p : s.points )
      if ( p.role != geostation::BundlePointResult::Role::Tie )
        pointRows << QStringList { text( p.id ), bundlePointRoleName( p.role ), QString::number( p.imageCount ),
                                   number( p.rmsPx, 3 ), number( p.errorM.x(), 3 ), number( p.errorM.y(), 3 ), number( p.errorM.z(), 3 ),
                                   number( p.sigmaM.x(), 3 ), number( p.sigmaM.y(), 3 ), number( p.sigmaM.z(), 3 ) };
    if ( !pointRows.isEmpty() )
    {
      page.heading( QObject::tr( "Control and check points" ) );
      page.paragraph( QObject::tr( "Error: adjusted minus known position." ) );
      page.table( { QObject::tr( "point" ), QObject::tr( "role" ), QObject::tr( "images" ), QObject::tr( "RMS (px)" ), QObject::tr( "error X (m)" ), QObject::tr( "error Y (m)" ),
                    QObject::tr( "error Z (m)" ), QObject::tr( "sigma X (m)" ), QObject::tr( "sigma Y (m)" ), QObject::tr( "sigma Z (m)" ) }, pointRows );
    }

    // every point, tie points too, by its RMS: the worst first
    std::vector<const geostation::BundlePointResult *> byRms;
    for ( const geostation::BundlePointResult &p : s.points )
      byRms.push_back( &p );
    std::stable_sort( byRms.begin(), byRms.end(), []( const auto *a, const auto *b ) { return a->rmsPx > b->rmsPx; } );
    QVector<QStringList> worstPoints;
    for ( size_t k = 0; k < byRms.size() && k < static_cast<size_t>( kMostResidualRows ); ++k )
      worstPoints << QStringList { text( byRms[k]->id ), bundlePointRoleName( byRms[k]->role ),
                                   QString::number( byRms[k]->imageCount ), number( byRms[k]->rmsPx, 3 ), number( byRms[k]->sigmaM.x(), 3 ), number( byRms[k]->sigmaM.y(), 3 ),
                                   number( byRms[k]->sigmaM.z(), 3 ) };
    page.heading( QObject::tr( "Points" ) );
    page.paragraph( QObject::tr( "The %1 of %2 points with the largest residual RMS:" ).arg( worstPoints.size() ).arg( s.points.size() ) );
    page.table( { QObject::tr( "point" ), QObject::tr( "role" ), QObject::tr( "images" ), QObject::tr( "RMS (px)" ), QObject::tr( "sigma X (m)" ), QObject::tr( "sigma Y (m)" ),
                  QObject::tr( "sigma Z (m)" ) }, worstPoints );

    page.heading( QObject::tr( "Residuals" ) );
    std::vector<const geostation::BundleObservationResult *> worst;
    for ( const geostation::BundleObservationResult &o : s.observations )
      worst.push_back( &o );
    std::stable_sort( worst.begin(), worst.end(), []( const auto *a, const auto *b ) { return a->residualPx.norm() > b->residualPx.norm(); } );
    QVector<QStringList> worstRows;
    for ( size_t k = 0; k < worst.size() && k < static_cast<size_t>( kMostResidualRows ); ++k )
      worstRows << QStringList { text( worst[k]->pointId ), text( worst[k]->imageId ), number( worst[k]->pixelInImage.x(), 1 ), number( worst[k]->pixelInImage.y(), 1 ),
                                 number( worst[k]->residualPx.x(), 3 ), number( worst[k]->residualPx.y(), 3 ), number( worst[k]->residualPx.norm(), 3 ) };
    page.paragraph( QObject::tr( "The %1 largest of %2 residuals (projected minus measured, pixels):" ).arg( worstRows.size() ).arg( s.observations.size() ) );
    page.table( { QObject::tr( "point" ), QObject::tr( "image" ), QObject::tr( "col" ), QObject::tr( "row" ), QObject::tr( "d col" ), QObject::tr( "d row" ), QObject::tr( "length" ) }, worstRows );
    QVector<double> all;
    for ( const geostation::BundleObservationResult &o : s.observations )
      all << o.residualPx.norm();
    page.histogram( QObject::tr( "Residual lengths of all observations (pixels)." ), all, QStringLiteral( "px" ) );

    // the images with the largest RMS, each with its residual vectors
    std::vector<const geostation::BundleImageResult *> plotted;
    for ( const geostation::BundleImageResult &i : s.images )
      if ( i.observationCount > 0 )
        plotted.push_back( &i );
    std::stable_sort( plotted.begin(), plotted.end(), []( const auto *a, const auto *b ) { return a->rmsPx > b->rmsPx; } );
    if ( plotted.size() > static_cast<size_t>( kMostPlots ) )
    {
      plotted.resize( kMostPlots );
      page.paragraph( QObject::tr( "The residual vectors of the %1 images with the largest RMS:" ).arg( kMostPlots ) );
    }
    for ( const geostation::BundleImageResult *i : plotted )
    {
      const geostation::BlockImage *image = block.findImage( i->id );
      const geostation::Camera *camera = image ? block.findCamera( image->cameraId ) : nullptr;
      if ( !camera )
        continue;
      QVector<ResidualArrow> arrows;
      for ( const geostation::BundleObservationResult &o : s.observations )
        if ( o.imageId == i->id )
          arrows << ResidualArrow { QPointF( o.pixelInImage.x(), o.pixelInImage.y() ), QPointF( o.residualPx.x(), o.residualPx.y() ), residualLabel( text( o.pointId ), o.residualPx ) };
      page.residualPlot( QObject::tr( "%1: %2 residuals, RMS %3 px, over its %4 x %5 frame." ).arg( text( i->id ) ).arg( arrows.size() ).arg( number( i->rmsPx, 3 ) ).arg( camera->width ).arg( camera->height ),
                         QSizeF( camera->width, camera->height ), arrows, QStringLiteral( "px" ) );
    }
    return page.toUtf8();
  }

  QByteArray resectionHtml( const geostation::ResectionSummary &s, const QString &imageId, const geostation::Camera &camera,
                            const std::map<std::string, Eigen::Vector2d> &measured )
  {
    HtmlReport page( QObject::tr( "Space resection of %1" ).arg( imageId ) );
    page.keyValues( { { QObject::tr( "image" ), imageId }, { QObject::tr( "camera" ), text( camera.id ) }, { QObject::tr( "sigma0" ), number( s.sigma0, 3 ) },
                      { QObject::tr( "redundancy" ), QString::number( s.redundancy ) }, { QObject::tr( "iterations" ), QString::number( s.iterations ) },
                      { QObject::tr( "converged" ), yesNo( s.converged ) }, { QObject::tr( "control points used" ), QString::number( s.controlCount ) },
                      { QObject::tr( "RMSE on control (px)" ), number( s.rmseControlPx, 3 ) }, { QObject::tr( "check points" ), QString::number( s.checkCount ) },
                      { QObject::tr( "RMSE on check (px)" ), s.checkCount ? number( s.rmseCheckPx, 3 ) : QStringLiteral( "-" ) },
                      { QObject::tr( "RMSE on check, on the ground (m)" ), s.checkCount ? number( s.rmseCheckM, 3 ) : QStringLiteral( "-" ) },
                      { QObject::tr( "blunders removed" ), s.blunders.empty() ? QObject::tr( "none" ) : joined( s.blunders ) } } );
    page.heading( QObject::tr( "Parameters" ) );
    page.table( { QObject::tr( "parameter" ), QObject::tr( "estimate" ), QObject::tr( "sigma" ), QObject::tr( "unit" ) }, parameterRows( s.parameterNames, s.estimates, s.sigmas ) );

    page.heading( QObject::tr( "Residuals per point" ) );
    page.paragraph( QObject::tr( "Projected minus measured, pixels; w is Baarda's normalised residual, r the redundancy number; check and blunder points also their error on the ground." ) );
    QVector<QStringList> rows;
    QVector<ResidualArrow> arrows;
    for ( const geostation::PointResidual &r : s.residuals )
    {
      const QString role = r.blunder ? QObject::tr( "blunder" ) : r.check ? QObject::tr( "check" ) : QObject::tr( "control" );
      rows << QStringList { text( r.pointId ), role, number( r.residualPx.x(), 3 ), number( r.residualPx.y(), 3 ), number( r.residualPx.norm(), 3 ),
                            r.check ? QStringLiteral( "-" ) : number( r.normalised, 2 ), r.check ? QStringLiteral( "-" ) : number( r.redundancy, 2 ),
                            r.check || r.blunder ? number( r.groundErrorM.head<2>().norm(), 3 ) : QStringLiteral( "-" ) };
      const auto at = measured.find( r.pointId );
      if ( at != measured.end() )
        arrows << ResidualArrow { QPointF( at->second.x(), at->second.y() ), QPointF( r.residualPx.x(), r.residualPx.y() ), residualLabel( text( r.pointId ) + " (" + role + ")", r.residualPx ), r.blunder };
    }
    page.table( { QObject::tr( "point" ), QObject::tr( "role" ), QObject::tr( "d col" ), QObject::tr( "d row" ), QObject::tr( "length" ), QStringLiteral( "w" ), QStringLiteral( "r" ),
                  QObject::tr( "ground error (m)" ) }, rows );
    page.residualPlot( QObject::tr( "Residual vectors over the %1 x %2 frame (blunders in red)." ).arg( camera.width ).arg( camera.height ), QSizeF( camera.width, camera.height ), arrows,
                       QStringLiteral( "px" ) );
    page.histogram( QObject::tr( "Residual lengths (pixels)." ), lengths( arrows ), QStringLiteral( "px" ) );
    return page.toUtf8();
  }

  QByteArray innerOrientationHtml( const geostation::InnerOrientationSummary &s, const QString &imageId, const QString &cameraId,
                                   const std::vector<geostation::FiducialMeasurement> &measured )
  {
    HtmlReport page( QObject::tr( "Inner orientation of %1" ).arg( imageId ) );
    const geostation::AffineDecomposition &d = s.decomposition;
    page.keyValues( { { QObject::tr( "image" ), imageId }, { QObject::tr( "camera" ), cameraId }, { QObject::tr( "fiducials" ), QString::number( measured.size() ) },
                      { QObject::tr( "redundancy" ), QString::number( s.redundancy ) }, { QObject::tr( "sigma0 (µm)" ), number( 1000.0 * s.sigma0Mm, 2 ) },
                      { QObject::tr( "residual RMS (µm)" ), number( 1000.0 * s.rmsResidualMm, 2 ) }, { QObject::tr( "scale A (mm per pixel)" ), number( d.scaleA, 7 ) },
                      { QObject::tr( "scale B (mm per pixel)" ), number( d.scaleB, 7 ) }, { QObject::tr( "direction of A (deg)" ), number( d.alphaADeg, 4 ) },
                      { QObject::tr( "affinity (%)" ), number( d.affinityPct, 4 ) }, { QObject::tr( "rotation beta (deg)" ), number( d.betaDeg, 4 ) },
                      { QObject::tr( "fiducial centre (col, row)" ), QStringLiteral( "%1, %2" ).arg( number( s.fiducialCentrePx.x(), 2 ), number( s.fiducialCentrePx.y(), 2 ) ) } } );
    page.heading( QObject::tr( "Residuals per fiducial" ) );
    page.paragraph( QObject::tr( "Transformed minus calibrated position, in the photo's coordinates (µm) and in scan pixels." ) );
    // a photo-coordinate residual in scan pixels: a acts on (col, -row)
    const Eigen::Matrix2d pixelFromPhoto = s.a.determinant() != 0.0 ? Eigen::Matrix2d( s.a.inverse() ) : Eigen::Matrix2d::Zero();
    QVector<QStringList> rows;
    QVector<ResidualArrow> arrows;
    double minCol = 1e300, minRow = 1e300, maxCol = -1e300, maxRow = -1e300;
    for ( const geostation::FiducialMeasurement &m : measured )
    {
      minCol = std::min( minCol, m.pixelInImage.x() );
      maxCol = std::max( maxCol, m.pixelInImage.x() );
      minRow = std::min( minRow, m.pixelInImage.y() );
      maxRow = std::max( maxRow, m.pixelInImage.y() );
    }
    const double margin = 0.05 * std::max( maxCol - minCol, maxRow - minRow );
    for ( const geostation::FiducialResidual &r : s.residuals )
    {
      const Eigen::Vector2d uv = pixelFromPhoto * r.residualMm;
      const Eigen::Vector2d px( uv.x(), -uv.y() );
      rows << QStringList { text( r.id ), number( 1000.0 * r.residualMm.x(), 2 ), number( 1000.0 * r.residualMm.y(), 2 ), number( 1000.0 * r.residualMm.norm(), 2 ),
                            number( px.x(), 3 ), number( px.y(), 3 ) };
      const auto at = std::find_if( measured.begin(), measured.end(), [&]( const geostation::FiducialMeasurement &m ) { return m.id == r.id; } );
      if ( at != measured.end() )
        arrows << ResidualArrow { QPointF( at->pixelInImage.x() - minCol + margin, at->pixelInImage.y() - minRow + margin ), QPointF( px.x(), px.y() ),
                                  QStringLiteral( "%1: %2 µm" ).arg( text( r.id ), number( 1000.0 * r.residualMm.norm(), 2 ) ) };
    }
    page.table( { QObject::tr( "fiducial" ), QObject::tr( "dx (µm)" ), QObject::tr( "dy (µm)" ), QObject::tr( "length (µm)" ), QObject::tr( "d col (px)" ), QObject::tr( "d row (px)" ) }, rows );
    if ( !measured.empty() )
      page.residualPlot( QObject::tr( "Residual vectors at the fiducials (scan pixels, the fiducials' extent)." ), QSizeF( maxCol - minCol + 2.0 * margin, maxRow - minRow + 2.0 * margin ), arrows,
                         QStringLiteral( "px" ) );
    QVector<double> micrometres;
    for ( const geostation::FiducialResidual &r : s.residuals )
      micrometres << 1000.0 * r.residualMm.norm();
    page.histogram( QObject::tr( "Residual lengths (µm)." ), micrometres, QStringLiteral( "µm" ) );
    return page.toUtf8();
  }

  QByteArray identifyControlHtml( const geostation::PhotoIdentificationSummary &s, const QString &imageId, int frameWidth, int frameHeight )
  {
    const geostation::ControlIdentificationSummary &c = s.identification;
    HtmlReport page( QObject::tr( "Control identified in %1" ).arg( imageId ) );
    page.keyValues( { { QObject::tr( "image" ), imageId }, { QObject::tr( "mark candidates" ), QString::number( s.candidates ) },
                      { QObject::tr( "control points identified" ), QString::number( s.identified.size() ) },
                      { QObject::tr( "of them measured at their prediction" ), QString::number( s.relocated ) },
                      { QObject::tr( "flagged (further than %1 px from the prediction)" ).arg( number( s.claimLimitPx, 2 ) ), QString::number( s.flagged.size() ) },
                      { QObject::tr( "in the photo, not found" ), QString::number( s.notFound.size() ) }, { QObject::tr( "rejected as blunders" ), QString::number( c.rejected.size() ) },
                      { QObject::tr( "triangle pairings tried" ), QString::number( c.triangles ) }, { QObject::tr( "poses scored" ), QString::number( c.poses ) },
                      { QObject::tr( "expected false alarms" ), QString::number( c.falseAlarms, 'g', 3 ) }, { QObject::tr( "resection sigma0" ), number( c.resection.sigma0, 3 ) },
                      { QObject::tr( "RMSE on control (px)" ), number( c.resection.rmseControlPx, 3 ) }, { QObject::tr( "time (s)" ), number( c.seconds, 1 ) } } );
    page.heading( QObject::tr( "Orientation found" ) );
    page.table( { QObject::tr( "parameter" ), QObject::tr( "estimate" ), QObject::tr( "sigma" ), QObject::tr( "unit" ) },
                parameterRows( c.resection.parameterNames, c.resection.estimates, c.resection.sigmas ) );

    page.heading( QObject::tr( "Residuals per point" ) );
    page.paragraph( QObject::tr( "Predicted by the orientation found minus measured, file pixels; flagged points in red, not claimed." ) );
    QVector<QStringList> rows;
    QVector<ResidualArrow> arrows;
    const auto add = [&]( const geostation::PhotoIdentifiedPoint &p, bool flagged ) {
      const Eigen::Vector2d r = p.predictedInFile - p.pixelInFile;
      rows << QStringList { text( p.pointId ), flagged ? QObject::tr( "flagged" ) : QObject::tr( "identified" ), number( p.pixelInFile.x(), 2 ), number( p.pixelInFile.y(), 2 ),
                            number( r.x(), 3 ), number( r.y(), 3 ), number( r.norm(), 3 ) };
      arrows << ResidualArrow { QPointF( p.pixelInFile.x(), p.pixelInFile.y() ), QPointF( r.x(), r.y() ), residualLabel( text( p.pointId ), r ), flagged };
    };
    for ( const geostation::PhotoIdentifiedPoint &p : s.identified )
      add( p, false );
    for ( const geostation::PhotoIdentifiedPoint &p : s.flagged )
      add( p, true );
    page.table( { QObject::tr( "point" ), QObject::tr( "status" ), QObject::tr( "col" ), QObject::tr( "row" ), QObject::tr( "d col" ), QObject::tr( "d row" ), QObject::tr( "length" ) }, rows );
    page.residualPlot( QObject::tr( "Residual vectors over the %1 x %2 photo." ).arg( frameWidth ).arg( frameHeight ), QSizeF( frameWidth, frameHeight ), arrows, QStringLiteral( "px" ) );
    page.histogram( QObject::tr( "Residual lengths (pixels)." ), lengths( arrows ), QStringLiteral( "px" ) );
    if ( !s.notFound.empty() )
    {
      QVector<QStringList> missing;
      for ( const auto &[id, predicted] : s.notFound )
        missing << QStringList { text( id ), number( predicted.x(), 1 ), number( predicted.y(), 1 ) };
      page.heading( QObject::tr( "In the photo, not found" ) );
      page.table( { QObject::tr( "point" ), QObject::tr( "predicted col" ), QObject::tr( "predicted row" ) }, missing );
    }
    return page.toUtf8();
  }

} // namespace GeoStationProcessing
