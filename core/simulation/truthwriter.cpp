/***************************************************************************
  truthwriter.cpp - truth lines, truth points, image truth and truth.gpkg
 ***************************************************************************/
#include "simulation/truthwriter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include "geometry/projection.h"
#include "simulation/filmscan.h"
#include "io/rasterfile.h"

namespace geostation
{
  namespace
  {
    std::string numbered( const std::string &prefix, int n )
    {
      char buffer[16];
      std::snprintf( buffer, sizeof buffer, "%03d", n );
      return prefix + buffer;
    }

    /**
     * Samples offset d of a road from s0 to s1 every `step` metres and keeps
     * the runs of vertices that belong to this road (on the terrain, not
     * under a road with priority); each run becomes one line.
     */
    void addRuns( const Scene &scene, int road, double s0, double s1, double d, double step, bool clip,
                  const TruthLine &pattern, std::vector<TruthLine> &out, int &counter )
    {
      const RoadNetwork &roads = scene.roads();
      std::vector<Eigen::Vector3d> run;
      const auto flush = [&]()
      {
        if ( run.size() >= 2 )
        {
          TruthLine line = pattern;
          line.id = numbered( pattern.id + "-", ++counter );
          line.vertices = run;
          out.push_back( line );
        }
        run.clear();
      };
      const int n = std::max( 1, static_cast<int>( std::ceil( ( s1 - s0 ) / step ) ) );
      for ( int k = 0; k <= n; ++k )
      {
        const double s = s0 + ( s1 - s0 ) * k / n;
        const Eigen::Vector2d p = roads.pointAt( road, s, d );
        const std::optional<double> z = scene.terrain().heightAt( p.x(), p.y() );
        bool keep = z.has_value();
        if ( keep && clip )
        {
          const std::optional<RoadLocation> at = roads.locate( p.x(), p.y() );
          keep = at && at->road == road;
        }
        if ( keep )
          run.emplace_back( p.x(), p.y(), *z );
        else
          flush();
      }
      flush();
    }

    struct DatasetCloser
    {
      void operator()( void *ds ) const { GDALClose( ds ); }
    };
  }

  std::vector<TruthLine> roadTruthLines( const Scene &scene )
  {
    std::vector<TruthLine> lines;
    const RoadNetwork &roads = scene.roads();
    for ( size_t r = 0; r < roads.roads().size(); ++r )
    {
      const Road &road = roads.roads()[r];
      const int ri = static_cast<int>( r );
      const double length = roads.length( ri );
      int counter = 0;
      addRuns( scene, ri, 0.0, length, 0.0, 2.0, false, { road.id + "-centre", "centre", road.id, "", {} }, lines, counter );
      counter = 0;
      addRuns( scene, ri, 0.0, length, road.halfWidthM(), 2.0, true, { road.id + "-edge-left", "edge", road.id, "", {} }, lines, counter );
      counter = 0;
      addRuns( scene, ri, 0.0, length, -road.halfWidthM(), 2.0, true, { road.id + "-edge-right", "edge", road.id, "", {} }, lines, counter );
      counter = 0;
      addRuns( scene, ri, 0.0, length, road.halfWidthM() + kKerbWidthM, 2.0, true, { road.id + "-kerb-left", "kerb", road.id, "", {} }, lines, counter );
      counter = 0;
      addRuns( scene, ri, 0.0, length, -( road.halfWidthM() + kKerbWidthM ), 2.0, true, { road.id + "-kerb-right", "kerb", road.id, "", {} }, lines, counter );
      int markingIndex = 0;
      for ( const RoadMarkingLine &marking : roadMarkings( road ) )
      {
        counter = 0;
        const TruthLine pattern { road.id + "-" + marking.kind + std::to_string( ++markingIndex ), "marking", road.id, marking.kind, {} };
        if ( !marking.dashed )
        {
          addRuns( scene, ri, 0.0, length, marking.offsetM, 2.0, true, pattern, lines, counter );
          continue;
        }
        for ( double s = 0.0; s + kDashM <= length; s += kDashM + kGapM )
          addRuns( scene, ri, s, s + kDashM, marking.offsetM, 1.5, true, pattern, lines, counter );
      }
    }
    return lines;
  }

  std::vector<TruthPoint> truthPoints( const Scene &scene, const std::vector<TruthLine> &lines )
  {
    std::vector<TruthPoint> points;
    for ( size_t i = 0; i < scene.objects().size(); ++i )
    {
      const SceneObject &object = scene.objects()[i];
      if ( object.kind == ObjectKind::Tree || object.kind == ObjectKind::Car )
        continue;
      points.push_back( { object.id, object.truthPoint(), static_cast<int>( i ) } );
    }
    for ( const GroundMark &mark : scene.marks() )
      points.push_back( { mark.id, mark.centre, -1, mark.kind == GroundMarkKind::Target ? &mark : nullptr } );
    for ( const TruthLine &line : lines )
      for ( size_t v = 0; v < line.vertices.size(); ++v )
        points.push_back( { line.id + ":" + std::to_string( v ), line.vertices[v], -1 } );
    return points;
  }

  TargetCover targetCoverInImage( const Scene &scene, const OrientedImage &image, const GroundMark &target )
  {
    TargetCover cover;
    const Eigen::Vector3d &centre = image.exterior().projectionCentre;
    // a film camera's fiducial marks are printed over the picture: dark squares 3 mark diameters wide
    std::vector<Eigen::Vector2d> fiducials;
    const Camera &camera = image.camera();
    if ( camera.pixelSizeMm )
      for ( const Fiducial &f : camera.fiducials )
        fiducials.push_back( fiducialNominalPixel( camera, f ) );
    const auto underAFiducial = [&]( const Eigen::Vector2d &pixel )
    {
      return std::any_of( fiducials.begin(), fiducials.end(), [&]( const Eigen::Vector2d &f ) { return ( pixel - f ).cwiseAbs().maxCoeff() <= kFiducialSquareHalfPx; } );
    };
    const double step = target.radiusM / 6.0, small = 0.25 * step;
    double total = 0.0, inView = 0.0, inSun = 0.0;
    const auto groundAt = [&]( double x, double y ) -> std::optional<Eigen::Vector3d>
    {
      const std::optional<double> h = scene.terrain().heightAt( x, y );
      return h ? std::optional<Eigen::Vector3d>( Eigen::Vector3d( x, y, *h ) ) : std::nullopt;
    };
    for ( int i = -6; i < 6; ++i )
      for ( int j = -6; j < 6; ++j )
      {
        const Eigen::Vector2d rel( ( i + 0.5 ) * step, ( j + 0.5 ) * step );
        if ( rel.norm() > target.radiusM )
          continue;
        const double x = target.centre.x() + rel.x(), y = target.centre.y() + rel.y();
        const std::optional<Eigen::Vector3d> p = groundAt( x, y ), px = groundAt( x + small, y ), py = groundAt( x, y + small );
        if ( !p || !px || !py )
          continue;
        const GroundProjection at = image.projectGroundToPixel( *p ), atX = image.projectGroundToPixel( *px ), atY = image.projectGroundToPixel( *py );
        if ( !at.ok() || !atX.ok() || !atY.ok() )
          continue;
        // the terrain cell's area in the image: the projection's Jacobian over the ground's x and y
        Eigen::Matrix2d jacobian;
        jacobian.col( 0 ) = ( atX.pixelInImage - at.pixelInImage ) / small;
        jacobian.col( 1 ) = ( atY.pixelInImage - at.pixelInImage ) / small;
        const double areaPx = std::abs( jacobian.determinant() ) * step * step;
        total += areaPx;
        if ( !at.inFrame || underAFiducial( at.pixelInImage ) || !scene.isVisible( centre, *p, -1, std::max( 0.02, 2e-4 * at.depthM ) ) )
          continue;
        inView += areaPx;
        if ( !scene.inShadow( p->head<2>() ) )
          inSun += areaPx;
      }
    cover.discPx = total;
    cover.inView = total > 0.0 ? inView / total : 0.0;
    cover.inSun = total > 0.0 ? inSun / total : 0.0;
    return cover;
  }

  std::vector<ImageTruthRow> imageTruth( const Scene &scene, const Block &block, const std::vector<TruthPoint> &points,
                                         const std::function<void( size_t )> &progress )
  {
    std::vector<ImageTruthRow> rows;
    size_t done = 0;
    for ( const BlockImage &image : block.images )
    {
      const OrientedImage oriented = block.orientedImage( image );
      const Eigen::Vector3d &centre = oriented.exterior().projectionCentre;
      for ( const TruthPoint &point : points )
      {
        const GroundProjection projection = oriented.projectGroundToPixel( point.point );
        if ( !projection.ok() || !projection.inFrame )
          continue;
        const double tolerance = std::max( 0.02, 2e-4 * projection.depthM );
        if ( !scene.isVisible( centre, point.point, point.ownObject, tolerance ) )
          continue;
        ImageTruthRow row { point.id, image.id, projection.pixelInImage.x(), projection.pixelInImage.y(), std::nullopt, std::nullopt, std::nullopt };
        if ( point.target )
        {
          const TargetCover cover = targetCoverInImage( scene, oriented, *point.target );
          row.discPx = cover.discPx;
          row.discInView = cover.inView;
          row.discInSun = cover.inSun;
        }
        rows.push_back( row );
      }
      if ( progress )
        progress( ++done );
    }
    return rows;
  }

  void writeTruthGeoPackage( const std::filesystem::path &path, const std::string &crs, const Scene &scene,
                             const std::vector<TruthLine> &lines, const std::vector<ImageTruthRow> &rows )
  {
    registerGdalDrivers();
    GDALDriverH driver = GDALGetDriverByName( "GPKG" );
    std::unique_ptr<void, DatasetCloser> ds( GDALCreate( driver, path.string().c_str(), 0, 0, 0, GDT_Unknown, nullptr ) );
    if ( !ds )
      throw std::runtime_error( "cannot create " + path.string() );
    OGRSpatialReferenceH srs = OSRNewSpatialReference( nullptr );
    OSRSetFromUserInput( srs, crs.c_str() );
    OSRSetAxisMappingStrategy( srs, OAMS_TRADITIONAL_GIS_ORDER );
    const auto createLayer = [&]( const char *name, OGRwkbGeometryType type, OGRSpatialReferenceH layerSrs,
                                  const std::vector<std::pair<const char *, OGRFieldType>> &fields )
    {
      OGRLayerH layer = GDALDatasetCreateLayer( ds.get(), name, layerSrs, type, nullptr );
      if ( !layer )
        throw std::runtime_error( std::string( "cannot create the layer " ) + name + " in " + path.string() );
      for ( const auto &[fieldName, fieldType] : fields )
      {
        OGRFieldDefnH field = OGR_Fld_Create( fieldName, fieldType );
        OGR_L_CreateField( layer, field, TRUE );
        OGR_Fld_Destroy( field );
      }
      return layer;
    };
    const auto addFeature = [&]( OGRLayerH layer, OGRGeometryH geometry, const std::vector<std::pair<int, std::string>> &texts,
                                 const std::vector<std::pair<int, double>> &numbers = {} )
    {
      OGRFeatureH feature = OGR_F_Create( OGR_L_GetLayerDefn( layer ) );
      for ( const auto &[index, value] : texts )
        OGR_F_SetFieldString( feature, index, value.c_str() );
      for ( const auto &[index, value] : numbers )
        OGR_F_SetFieldDouble( feature, index, value );
      if ( geometry )
        OGR_F_SetGeometryDirectly( feature, geometry );
      const OGRErr err = OGR_L_CreateFeature( layer, feature );
      OGR_F_Destroy( feature );
      if ( err != OGRERR_NONE )
        throw std::runtime_error( "cannot write a feature to " + path.string() );
    };
    const auto pointZ = []( const Eigen::Vector3d &p )
    {
      OGRGeometryH g = OGR_G_CreateGeometry( wkbPoint25D );
      OGR_G_SetPoint( g, 0, p.x(), p.y(), p.z() );
      return g;
    };

    GDALDatasetStartTransaction( ds.get(), FALSE );
    OGRLayerH objects = createLayer( "objects", wkbPoint25D, srs, { { "id", OFTString }, { "kind", OFTString } } );
    OGRLayerH occluders = createLayer( "occluders", wkbPoint25D, srs, { { "id", OFTString }, { "kind", OFTString }, { "height_m", OFTReal } } );
    for ( const SceneObject &object : scene.objects() )
    {
      if ( object.kind == ObjectKind::Tree || object.kind == ObjectKind::Car )
        addFeature( occluders, pointZ( object.base ), { { 0, object.id }, { 1, objectKindName( object.kind ) } }, { { 2, object.heightM() } } );
      else
        addFeature( objects, pointZ( object.truthPoint() ), { { 0, object.id }, { 1, objectKindName( object.kind ) } } );
    }
    OGRLayerH control = createLayer( "control", wkbPoint25D, srs, { { "id", OFTString } } );
    for ( const GroundMark &mark : scene.marks() )
    {
      if ( mark.kind == GroundMarkKind::Manhole )
        addFeature( objects, pointZ( mark.centre ), { { 0, mark.id }, { 1, "manhole" } } );
      else
        addFeature( control, pointZ( mark.centre ), { { 0, mark.id } } );
    }
    OGRLayerH roads = createLayer( "roads", wkbLineString25D, srs, { { "id", OFTString }, { "kind", OFTString }, { "road", OFTString }, { "marking", OFTString } } );
    for ( const TruthLine &line : lines )
    {
      OGRGeometryH g = OGR_G_CreateGeometry( wkbLineString25D );
      for ( const Eigen::Vector3d &v : line.vertices )
        OGR_G_AddPoint( g, v.x(), v.y(), v.z() );
      std::vector<std::pair<int, std::string>> texts { { 0, line.id }, { 1, line.kind }, { 2, line.road } };
      if ( !line.marking.empty() )
        texts.push_back( { 3, line.marking } );
      addFeature( roads, g, texts );
    }
    OGRLayerH table = createLayer( "image_truth", wkbNone, nullptr,
                                   { { "point_id", OFTString }, { "image_id", OFTString }, { "col", OFTReal }, { "row", OFTReal },
                                     { "disc_px", OFTReal }, { "disc_in_view", OFTReal }, { "disc_in_sun", OFTReal } } );
    for ( const ImageTruthRow &row : rows )
    {
      std::vector<std::pair<int, double>> numbers { { 2, row.col }, { 3, row.row } };
      if ( row.discPx )
        numbers.insert( numbers.end(), { { 4, *row.discPx }, { 5, *row.discInView }, { 6, *row.discInSun } } );
      addFeature( table, nullptr, { { 0, row.pointId }, { 1, row.imageId } }, numbers );
    }
    if ( GDALDatasetCommitTransaction( ds.get() ) != OGRERR_NONE )
    {
      OSRDestroySpatialReference( srs );
      throw std::runtime_error( "cannot write " + path.string() );
    }
    OSRDestroySpatialReference( srs );
  }

} // namespace geostation
