/***************************************************************************
  processingtables.cpp - the tables algorithms exchange
 ***************************************************************************/
#include "processingtables.h"

#include <cmath>

#include <qgscoordinatetransform.h>
#include <qgsexception.h>
#include <qgsfeatureiterator.h>
#include <qgsfeaturesource.h>
#include <qgsgeometry.h>
#include <qgsprocessingfeedback.h>

#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

  namespace
  {
    int fieldIndex( const QgsFields &fields, const QString &name )
    {
      for ( int i = 0; i < fields.count(); ++i )
        if ( fields.at( i ).name().compare( name, Qt::CaseInsensitive ) == 0 )
          return i;
      return -1;
    }

    int requireField( const QgsFields &fields, const QString &name, const QString &what, const QString &expected )
    {
      const int index = fieldIndex( fields, name );
      if ( index < 0 )
        throw QgsProcessingException( QObject::tr( "The %1 table has no field \"%2\"; it needs %3." ).arg( what, name, expected ) );
      return index;
    }

    QString text( const QgsFeature &f, int index )
    {
      const QVariant v = f.attribute( index );
      return v.isNull() ? QString() : v.toString().trimmed();
    }

    //! A number from a numeric or text field; throws naming the row and field.
    double number( const QgsFeature &f, int index, long row, const QString &field, const QString &what, bool optional = false, double fallback = 0.0 )
    {
      const QVariant v = f.attribute( index );
      if ( v.isNull() || ( v.type() == QVariant::String && v.toString().trimmed().isEmpty() ) )
      {
        if ( optional )
          return fallback;
        throw QgsProcessingException( QObject::tr( "Row %1 of the %2 table has no value in \"%3\"." ).arg( row ).arg( what, field ) );
      }
      bool ok = false;
      const double d = v.type() == QVariant::String ? v.toString().trimmed().toDouble( &ok ) : v.toDouble( &ok );
      if ( !ok || !std::isfinite( d ) )
        throw QgsProcessingException( QObject::tr( "Row %1 of the %2 table: \"%3\" is \"%4\", not a number." ).arg( row ).arg( what, field, v.toString() ) );
      return d;
    }
  } // namespace

  KnownPositionTable readKnownPositions( QgsFeatureSource *source, const QString &what )
  {
    const QString expected = QObject::tr( "image, X, Y, Z (camera centres by the model's image name) or point_id, X, Y, Z (control points by the model's point id)" );
    const QgsFields fields = source->fields();
    KnownPositionTable table;
    int nameField = fieldIndex( fields, QStringLiteral( "image" ) );
    if ( nameField < 0 )
    {
      nameField = requireField( fields, QStringLiteral( "point_id" ), what, expected );
      table.cameraCentres = false;
    }
    const int xyz[3] = { requireField( fields, QStringLiteral( "X" ), what, expected ), requireField( fields, QStringLiteral( "Y" ), what, expected ),
                         requireField( fields, QStringLiteral( "Z" ), what, expected ) };
    const char *names[3] = { "X", "Y", "Z" };
    QgsFeature f;
    QgsFeatureIterator it = source->getFeatures();
    long row = 0;
    while ( it.nextFeature( f ) )
    {
      ++row;
      const QString name = text( f, nameField );
      if ( name.isEmpty() )
        throw QgsProcessingException( QObject::tr( "Row %1 of the %2 table has no value in \"%3\"." ).arg( row ).arg( what, fields.at( nameField ).name() ) );
      Eigen::Vector3d p;
      for ( int k = 0; k < 3; ++k )
        p[k] = number( f, xyz[k], row, QString::fromLatin1( names[k] ), what );
      table.rows.append( qMakePair( name, p ) );
    }
    return table;
  }

  ObservationTable readObservations( QgsFeatureSource *source, const QString &what, QgsProcessingFeedback *feedback )
  {
    const QString expected = QObject::tr( "point_id, image_id, col, row and optionally sigma_px" );
    const QgsFields fields = source->fields();
    const int pointField = requireField( fields, QStringLiteral( "point_id" ), what, expected );
    const int imageField = requireField( fields, QStringLiteral( "image_id" ), what, expected );
    const int colField = requireField( fields, QStringLiteral( "col" ), what, expected );
    const int rowField = requireField( fields, QStringLiteral( "row" ), what, expected );
    const int sigmaField = fieldIndex( fields, QStringLiteral( "sigma_px" ) );
    // match_points' and identify_control's output: rows of failed matches (status no_peak, ambiguous, not_found, ...) carry no col/row and are no observations
    const int statusField = fieldIndex( fields, QStringLiteral( "status" ) );
    const QStringList observed { QStringLiteral( "lsm" ), QStringLiteral( "correlation" ), QStringLiteral( "reference" ), QStringLiteral( "identified" ) };

    ObservationTable table;
    QList<int> extraIndexes;
    for ( int i = 0; i < fields.count(); ++i )
      if ( i != pointField && i != imageField && i != colField && i != rowField && i != sigmaField )
      {
        table.extraFields.append( fields.at( i ) );
        extraIndexes << i;
      }

    QgsFeatureIterator it = source->getFeatures( QgsFeatureRequest().setFlags( QgsFeatureRequest::NoGeometry ) );
    QgsFeature f;
    long row = 0;
    while ( it.nextFeature( f ) )
    {
      ++row;
      if ( feedback && feedback->isCanceled() )
        break;
      ObservationRecord r;
      r.pointId = text( f, pointField );
      r.imageId = text( f, imageField );
      if ( r.pointId.isEmpty() || r.imageId.isEmpty() )
        throw QgsProcessingException( QObject::tr( "Row %1 of the %2 table has no point_id or no image_id." ).arg( row ).arg( what ) );
      if ( statusField >= 0 && !text( f, statusField ).isEmpty() && !observed.contains( text( f, statusField ).trimmed().toLower() ) )
      {
        ++table.failedMatches;
        continue;
      }
      r.pixel = Eigen::Vector2d( number( f, colField, row, QStringLiteral( "col" ), what ), number( f, rowField, row, QStringLiteral( "row" ), what ) );
      if ( sigmaField >= 0 )
      {
        r.sigmaPx = number( f, sigmaField, row, QStringLiteral( "sigma_px" ), what, true, 0.0 );
        if ( r.sigmaPx < 0.0 || ( r.sigmaPx == 0.0 && !text( f, sigmaField ).isEmpty() ) )
          throw QgsProcessingException( QObject::tr( "Row %1 of the %2 table: sigma_px must be positive." ).arg( row ).arg( what ) );
      }
      for ( int i : extraIndexes )
        r.extra << f.attribute( i );
      table.rows << r;
    }
    if ( feedback && table.failedMatches > 0 )
      feedback->pushInfo( QObject::tr( "%n row(s) of the %1 table are failed matches (their status) and were left out.", nullptr, table.failedMatches ).arg( what ) );
    return table;
  }

  QVector<GroundPointRecord> readGroundPoints( QgsFeatureSource *source, const QString &what, const QgsCoordinateReferenceSystem &blockCrs,
      const QgsCoordinateTransformContext &transformContext, QgsProcessingFeedback *feedback, const HeightSource &heightOf )
  {
    const QgsFields fields = source->fields();
    // a point layer's own "id" (the simulator's control layer, many GIS layers) names its points where there is no point_id
    const int pointField = fieldIndex( fields, QStringLiteral( "point_id" ) ) < 0 && fieldIndex( fields, QStringLiteral( "id" ) ) >= 0 && source->wkbType() != QgsWkbTypes::NoGeometry
                           ? fieldIndex( fields, QStringLiteral( "id" ) )
                           : requireField( fields, QStringLiteral( "point_id" ), what, QObject::tr( "point_id, X, Y, Z (or PointZ geometries) and optionally sx, sy, sz, role" ) );
    const int xField = fieldIndex( fields, QStringLiteral( "X" ) ), yField = fieldIndex( fields, QStringLiteral( "Y" ) ), zField = fieldIndex( fields, QStringLiteral( "Z" ) );
    const bool fromFields = xField >= 0 && yField >= 0 && ( zField >= 0 || heightOf );
    if ( !fromFields && !QgsWkbTypes::hasZ( source->wkbType() ) && !( heightOf && QgsWkbTypes::geometryType( source->wkbType() ) == QgsWkbTypes::PointGeometry ) )
      throw QgsProcessingException( QObject::tr( "The %1 table has neither X, Y, Z fields nor PointZ geometries." ).arg( what ) );
    // a point without height takes the DEM's, where a DEM is given
    auto height = [&]( double x, double y, const QString &pointId ) {
      const std::optional<double> z = heightOf ? heightOf( x, y ) : std::nullopt;
      if ( !z )
        throw QgsProcessingException( heightOf ? QObject::tr( "Point %1 of the %2 table has no height and the DEM does not cover it." ).arg( pointId, what )
                                      : QObject::tr( "Point %1 of the %2 table has no height." ).arg( pointId, what ) );
      return *z;
    };
    const int sigmaFields[3] = { fieldIndex( fields, QStringLiteral( "sx" ) ), fieldIndex( fields, QStringLiteral( "sy" ) ), fieldIndex( fields, QStringLiteral( "sz" ) ) };
    const int roleField = fieldIndex( fields, QStringLiteral( "role" ) );
    // Coordinates in fields are taken to be in the block CRS; geometries are transformed.
    const QgsCoordinateTransform toBlock( source->sourceCrs().isValid() ? source->sourceCrs() : blockCrs, blockCrs, transformContext );

    QVector<GroundPointRecord> points;
    QgsFeatureIterator it = source->getFeatures();
    QgsFeature f;
    long row = 0;
    while ( it.nextFeature( f ) )
    {
      ++row;
      if ( feedback && feedback->isCanceled() )
        break;
      GroundPointRecord p;
      p.pointId = text( f, pointField );
      if ( p.pointId.isEmpty() )
        throw QgsProcessingException( QObject::tr( "Row %1 of the %2 table has no point_id." ).arg( row ).arg( what ) );
      if ( fromFields )
      {
        const double x = number( f, xField, row, QStringLiteral( "X" ), what ), y = number( f, yField, row, QStringLiteral( "Y" ), what );
        const bool hasZ = zField >= 0 && !( f.attribute( zField ).isNull() || f.attribute( zField ).toString().trimmed().isEmpty() );
        p.world = Eigen::Vector3d( x, y, hasZ || !heightOf ? number( f, zField, row, QStringLiteral( "Z" ), what ) : height( x, y, p.pointId ) );
      }
      else
      {
        if ( !f.hasGeometry() )
          throw QgsProcessingException( QObject::tr( "Row %1 (%2) of the %3 table has no geometry." ).arg( row ).arg( p.pointId, what ) );
        if ( f.geometry().isEmpty() )
          throw QgsProcessingException( QObject::tr( "Row %1 (%2) of the %3 table has an empty geometry: it gives no position." ).arg( row ).arg( p.pointId, what ) );
        const QgsPoint point = *f.geometry().vertices_begin();
        double x = point.x(), y = point.y(), z = point.z();
        const bool hasZ = !std::isnan( z );
        if ( !hasZ && !heightOf )
          throw QgsProcessingException( QObject::tr( "Point %1 of the %2 table has no height." ).arg( p.pointId, what ) );
        if ( !hasZ )
          z = 0.0;
        try
        {
          toBlock.transformInPlace( x, y, z );
        }
        catch ( const QgsCsException & )
        {
          throw QgsProcessingException( QObject::tr( "Point %1 of the %2 table cannot be transformed to the block CRS." ).arg( p.pointId, what ) );
        }
        p.world = Eigen::Vector3d( x, y, hasZ ? z : height( x, y, p.pointId ) );
      }
      if ( !( p.world.cwiseAbs().maxCoeff() <= geostation::kMaxPlausibleCoordinateM ) )
        throw QgsProcessingException( QObject::tr( "Point %1 of the %2 table lies beyond any plausible position (X %3, Y %4, Z %5 m): coordinates in a projected CRS stay within 100 000 km." )
                                      .arg( p.pointId, what ).arg( p.world.x(), 0, 'g', 6 ).arg( p.world.y(), 0, 'g', 6 ).arg( p.world.z(), 0, 'g', 6 ) );
      const char *axes[3] = { "sx", "sy", "sz" };
      for ( int k = 0; k < 3; ++k )
        if ( sigmaFields[k] >= 0 )
        {
          p.sigmaM[k] = number( f, sigmaFields[k], row, QString::fromLatin1( axes[k] ), what, true, 0.0 );
          if ( p.sigmaM[k] < 0.0 )
            throw QgsProcessingException( QObject::tr( "Row %1 of the %2 table: %3 must not be negative." ).arg( row ).arg( what, QString::fromLatin1( axes[k] ) ) );
        }
      if ( roleField >= 0 )
      {
        const QString role = text( f, roleField ).toLower();
        if ( role == QLatin1String( "check" ) )
          p.check = true;
        else if ( !role.isEmpty() && role != QLatin1String( "control" ) )
          throw QgsProcessingException( QObject::tr( "Row %1 of the %2 table: role is \"%3\"; it must be control or check." ).arg( row ).arg( what, role ) );
      }
      points << p;
    }
    return points;
  }

  QVector<FiducialRecord> readFiducials( QgsFeatureSource *source, const QString &imageId )
  {
    const QString what = QObject::tr( "fiducials" );
    const QString expected = QObject::tr( "fiducial_id, col, row (and optionally image_id)" );
    const QgsFields fields = source->fields();
    const int idField = requireField( fields, QStringLiteral( "fiducial_id" ), what, expected );
    const int colField = requireField( fields, QStringLiteral( "col" ), what, expected );
    const int rowField = requireField( fields, QStringLiteral( "row" ), what, expected );
    const int imageField = fieldIndex( fields, QStringLiteral( "image_id" ) );
    QVector<FiducialRecord> records;
    QgsFeatureIterator it = source->getFeatures( QgsFeatureRequest().setFlags( QgsFeatureRequest::NoGeometry ) );
    QgsFeature f;
    long row = 0;
    while ( it.nextFeature( f ) )
    {
      ++row;
      if ( imageField >= 0 && text( f, imageField ) != imageId )
        continue;
      FiducialRecord r;
      r.fiducialId = text( f, idField );
      if ( r.fiducialId.isEmpty() )
        throw QgsProcessingException( QObject::tr( "Row %1 of the fiducials table has no fiducial_id." ).arg( row ) );
      r.pixel = Eigen::Vector2d( number( f, colField, row, QStringLiteral( "col" ), what ), number( f, rowField, row, QStringLiteral( "row" ), what ) );
      records << r;
    }
    return records;
  }

  std::vector<geostation::ControlPair> readControlPairs( QgsFeatureSource *source )
  {
    const QgsFields fields = source->fields();
    QVector<int> index;
    for ( const QString &name : { QStringLiteral( "point_id" ), QStringLiteral( "col_left" ), QStringLiteral( "row_left" ), QStringLiteral( "col_right" ), QStringLiteral( "row_right" ) } )
    {
      index << fields.lookupField( name );
      if ( index.back() < 0 )
        throw QgsProcessingException( QObject::tr( "The CONTROL table has no field %1 (it needs point_id, col_left, row_left, col_right, row_right)." ).arg( name ) );
    }
    std::vector<geostation::ControlPair> pairs;
    QgsFeature f;
    QgsFeatureIterator it = source->getFeatures();
    while ( it.nextFeature( f ) )
    {
      double v[4];
      for ( int k = 0; k < 4; ++k )
      {
        bool ok = false;
        v[k] = f.attribute( index[k + 1] ).toString().toDouble( &ok );
        if ( !ok || !std::isfinite( v[k] ) )
          throw QgsProcessingException( QObject::tr( "CONTROL row %1: %2 is not a number." ).arg( pairs.size() + 1 ).arg( fields.at( index[k + 1] ).name() ) );
      }
      pairs.push_back( { f.attribute( index[0] ).toString().toStdString(), Eigen::Vector2d( v[0], v[1] ), Eigen::Vector2d( v[2], v[3] ) } );
    }
    return pairs;
  }

  QVector<TraceSeedRecord> readTraceSeeds( QgsFeatureSource *source )
  {
    const QgsFields fields = source->fields();
    const auto field = [&]( const QString &name, bool required )
    {
      const int i = fields.lookupField( name );
      if ( i < 0 && required )
        throw QgsProcessingException( QObject::tr( "The SEEDS table has no field %1 (it needs seed_id, image_id, col, row and optionally direction_deg)." ).arg( name ) );
      return i;
    };
    const int id = field( QLatin1String( fs::kSeedId ), true ), image = field( QLatin1String( fs::kImageId ), true ), col = field( QLatin1String( fs::kCol ), true ),
              row = field( QLatin1String( fs::kRow ), true ), direction = field( QStringLiteral( "direction_deg" ), false );
    QVector<TraceSeedRecord> rows;
    QgsFeature f;
    QgsFeatureIterator it = source->getFeatures();
    while ( it.nextFeature( f ) )
    {
      const auto number = [&]( int index, const QString &name )
      {
        bool ok = false;
        const double v = f.attribute( index ).toString().toDouble( &ok );
        if ( !ok || !std::isfinite( v ) )
          throw QgsProcessingException( QObject::tr( "SEEDS row %1: %2 is not a number (\"%3\")." ).arg( rows.size() + 1 ).arg( name, f.attribute( index ).toString() ) );
        return v;
      };
      TraceSeedRecord r;
      r.seed.id = f.attribute( id ).toString().toStdString();
      r.seed.imageId = f.attribute( image ).toString().trimmed().toStdString();
      r.seed.pixelInImage = Eigen::Vector2d( number( col, QStringLiteral( "col" ) ), number( row, QStringLiteral( "row" ) ) );
      if ( direction >= 0 && !f.attribute( direction ).isNull() && !f.attribute( direction ).toString().trimmed().isEmpty() )
        r.seed.directionDeg = number( direction, QStringLiteral( "direction_deg" ) );
      r.attributes = f.attributes();
      rows << r;
    }
    if ( rows.isEmpty() )
      throw QgsProcessingException( QObject::tr( "The SEEDS table is empty." ) );
    return rows;
  }
}
