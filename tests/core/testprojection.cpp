// Ground <-> pixel with exterior orientation: p = R^T (P - X0).
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "geometry/lineprojection.h"
#include "geometry/projection.h"
#include "pinholecamera.h"

using namespace geostation;

namespace
{
  Camera vanCamera()
  {
    Camera c = centredPinhole( "front", 640, 480, 600.0 );
    c.distortion.model = DistortionModel::OpenCV;
    c.distortion.coeffs = { -0.2, 0.05, 0.0, 0.0, 0.0 };
    return c;
  }

  ExteriorOrientation lookingNorth()
  {
    ExteriorOrientation eo;
    eo.projectionCentre = { 500100.0, 4400200.0, 212.0 };
    eo.omegaDeg = 90.0; // horizontal, toward +Y
    return eo;
  }
} // namespace

TEST( Projection, PointOnTheAxisHitsThePrincipalPoint )
{
  const Camera c = vanCamera();
  const ExteriorOrientation eo = lookingNorth();
  const GroundProjection g = projectGroundToPixel( c, eo, eo.projectionCentre + Eigen::Vector3d( 0, 25, 0 ) );
  ASSERT_TRUE( g.ok() );
  EXPECT_NEAR( g.pixelInImage.x(), 320.0, 1e-9 );
  EXPECT_NEAR( g.pixelInImage.y(), 240.0, 1e-9 );
  EXPECT_NEAR( g.depthM, 25.0, 1e-9 );
  EXPECT_TRUE( g.inFrame );
}

TEST( Projection, LookingNorthEastIsRightAndUpIsUp )
{
  const Camera c = vanCamera();
  const ExteriorOrientation eo = lookingNorth();
  const GroundProjection east = projectGroundToPixel( c, eo, eo.projectionCentre + Eigen::Vector3d( 2, 25, 0 ) );
  const GroundProjection high = projectGroundToPixel( c, eo, eo.projectionCentre + Eigen::Vector3d( 0, 25, 2 ) );
  EXPECT_GT( east.pixelInImage.x(), 320.0 );
  EXPECT_LT( high.pixelInImage.y(), 240.0 );
}

TEST( Projection, PointBehindTheCameraIsNotProjected )
{
  const Camera c = vanCamera();
  const ExteriorOrientation eo = lookingNorth();
  const GroundProjection g = projectGroundToPixel( c, eo, eo.projectionCentre + Eigen::Vector3d( 0, -25, 0 ) );
  EXPECT_EQ( g.status, PixelProjection::Status::BehindCamera );
  EXPECT_FALSE( g.inFrame );
  EXPECT_NEAR( g.depthM, -25.0, 1e-9 );
}

TEST( Projection, OutsideTheFrameIsProjectedButFlagged )
{
  const Camera c = vanCamera();
  const ExteriorOrientation eo = lookingNorth();
  // 0.8 normalised: beyond the frame edge (0.53), inside the lens field (2 x 0.67)
  const GroundProjection g = projectGroundToPixel( c, eo, eo.projectionCentre + Eigen::Vector3d( 8, 10, 0 ) );
  ASSERT_TRUE( g.ok() );
  EXPECT_FALSE( g.inFrame );
  EXPECT_GT( g.pixelInImage.x(), 640.0 );
  // 2.0 normalised: far outside, where the lens polynomial is not trusted
  const GroundProjection far = projectGroundToPixel( c, eo, eo.projectionCentre + Eigen::Vector3d( 20, 10, 0 ) );
  EXPECT_EQ( far.status, PixelProjection::Status::OutsideLensField );
  EXPECT_FALSE( far.inFrame );
}

TEST( Projection, RayThroughProjectedPixelPassesThroughTheGroundPoint )
{
  const Camera c = vanCamera();
  std::mt19937 rng( 3 );
  std::uniform_real_distribution<double> angle( -30.0, 30.0 );
  std::uniform_real_distribution<double> offset( -6.0, 6.0 );
  for ( int i = 0; i < 500; ++i )
  {
    ExteriorOrientation eo = lookingNorth();
    eo.omegaDeg += angle( rng ) / 3;
    eo.phiDeg = angle( rng ) / 3;
    eo.kappaDeg = angle( rng );
    const Eigen::Vector3d ground = eo.projectionCentre + eo.viewingDirection() * 20.0 + Eigen::Vector3d( offset( rng ), offset( rng ), offset( rng ) );
    const GroundProjection g = projectGroundToPixel( c, eo, ground );
    ASSERT_TRUE( g.ok() );
    const std::optional<Ray> ray = worldRayFromPixel( c, eo, g.pixelInImage );
    ASSERT_TRUE( ray.has_value() );
    EXPECT_NEAR( ray->direction.norm(), 1.0, 1e-14 );
    const Eigen::Vector3d toPoint = ground - ray->origin;
    const double missM = ( toPoint - ray->direction * toPoint.dot( ray->direction ) ).norm();
    EXPECT_LT( missM, 1e-9 );
    EXPECT_GT( toPoint.dot( ray->direction ), 0.0 );
  }
}

TEST( Projection, OrientedImageAgreesWithTheFreeFunctions )
{
  const Camera c = vanCamera();
  ExteriorOrientation eo = lookingNorth();
  eo.phiDeg = 3.0;
  eo.kappaDeg = -7.0;
  const OrientedImage image( c, eo );
  for ( const Eigen::Vector3d &offset : { Eigen::Vector3d( 1, 20, -1 ), Eigen::Vector3d( -3, 8, 0.5 ), Eigen::Vector3d( 0, -5, 0 ), Eigen::Vector3d( 30, 5, 0 ) } )
  {
    const GroundProjection a = image.projectGroundToPixel( eo.projectionCentre + offset );
    const GroundProjection b = projectGroundToPixel( c, eo, eo.projectionCentre + offset );
    EXPECT_EQ( a.status, b.status );
    EXPECT_EQ( a.inFrame, b.inFrame );
    EXPECT_EQ( a.pixelInImage, b.pixelInImage );
    EXPECT_DOUBLE_EQ( a.depthM, b.depthM );
  }
  const Ray r = *image.worldRayFromPixel( { 100.5, 50.25 } );
  EXPECT_LT( ( r.direction - worldRayFromPixel( c, eo, { 100.5, 50.25 } )->direction ).norm(), 1e-15 );
}

TEST( Projection, RingsAreClippedToWhatTheImageCanProject )
{
  const OrientedImage image( vanCamera(), lookingNorth() );
  const Eigen::Vector3d c = image.exterior().projectionCentre;
  const double groundZ = c.z() - 2.5;
  // a paved area under and around the van: half of it behind the camera, much of it outside the lens field
  const std::vector<Eigen::Vector3d> around { { c.x() - 20, c.y() - 15, groundZ }, { c.x() + 20, c.y() - 15, groundZ },
    { c.x() + 20, c.y() + 40, groundZ }, { c.x() - 20, c.y() + 40, groundZ } };
  for ( const Eigen::Vector3d &v : around )
    EXPECT_FALSE( image.projectGroundToPixel( v ).ok() && v.y() < c.y() ); // the rear corners cannot be projected
  const std::vector<Eigen::Vector3d> clipped = clipRingToImageField( image, around );
  ASSERT_GE( clipped.size(), 3u );
  // every point of the clipped ring, vertices and edges, projects
  for ( size_t i = 0; i < clipped.size(); ++i )
  {
    EXPECT_NEAR( clipped[i].z(), groundZ, 1e-9 ); // on the original plane
    for ( double t = 0; t <= 1.0; t += 0.05 )
    {
      const Eigen::Vector3d p = clipped[i] + t * ( clipped[( i + 1 ) % clipped.size()] - clipped[i] );
      EXPECT_TRUE( image.projectGroundToPixel( p ).ok() ) << i << " " << t;
    }
    EXPECT_GT( clipped[i].y(), c.y() ); // in front (the camera looks north)
  }
  // what the frame shows of the area is kept: a ground point in the frame centre's lower half is inside
  const Eigen::Vector3d seen = image.worldRayFromPixel( { 320.5, 400.5 } )->origin
                               + ( ( groundZ - c.z() ) / image.worldRayFromPixel( { 320.5, 400.5 } )->direction.z() ) * image.worldRayFromPixel( { 320.5, 400.5 } )->direction;
  bool inside = false;
  for ( size_t i = 0, j = clipped.size() - 1; i < clipped.size(); j = i++ )
    if ( ( clipped[i].y() > seen.y() ) != ( clipped[j].y() > seen.y() )
         && seen.x() < ( clipped[j].x() - clipped[i].x() ) * ( seen.y() - clipped[i].y() ) / ( clipped[j].y() - clipped[i].y() ) + clipped[i].x() )
      inside = !inside;
  EXPECT_TRUE( inside );

  // a ring wholly in view is unchanged; one wholly behind is gone
  const std::vector<Eigen::Vector3d> ahead { { c.x() - 1, c.y() + 20, groundZ }, { c.x() + 1, c.y() + 20, groundZ }, { c.x(), c.y() + 22, groundZ } };
  const std::vector<Eigen::Vector3d> same = clipRingToImageField( image, ahead );
  ASSERT_EQ( same.size(), 3u );
  for ( size_t i = 0; i < 3; ++i )
    EXPECT_LT( ( same[i] - ahead[i] ).norm(), 1e-9 );
  std::vector<Eigen::Vector3d> behind = ahead;
  for ( Eigen::Vector3d &v : behind )
    v.y() = 2 * c.y() - v.y();
  EXPECT_TRUE( clipRingToImageField( image, behind ).empty() );
  EXPECT_THROW( clipRingToImageField( image, ahead, 0.0 ), std::invalid_argument );
}

TEST( Projection, PolylineCutWhereItLeavesTheProjectableField )
{
  // a field that ends at x = 10 and starts again at x = 14: the line is cut at both boundaries
  const GroundToPixel project = []( const Eigen::Vector3d &g ) -> std::optional<Eigen::Vector2d>
  {
    if ( g.x() > 10.0 && g.x() < 14.0 )
      return std::nullopt;
    return Eigen::Vector2d( 2.0 * g.x(), g.y() );
  };
  std::vector<Eigen::Vector3d> dense;
  for ( int i = 0; i <= 20; ++i )
    dense.emplace_back( i + 0.5, 1.0, 0.0 );
  const ProjectedPolylineParts cut = projectPolylineCut( dense, project );
  ASSERT_EQ( cut.parts.size(), 2u );
  EXPECT_EQ( cut.longest, 0 );
  EXPECT_NEAR( cut.parts[0].front().x(), 1.0, 1e-12 );
  EXPECT_NEAR( cut.parts[0].back().x(), 20.0, 1e-6 ); // the boundary x = 10, not the last vertex in the field (9.5)
  EXPECT_NEAR( cut.parts[1].front().x(), 28.0, 1e-6 ); // x = 14
  EXPECT_NEAR( cut.parts[1].back().x(), 41.0, 1e-12 );
  // nothing in the field: no part
  EXPECT_EQ( projectPolylineCut( { Eigen::Vector3d( 11, 0, 0 ), Eigen::Vector3d( 13, 0, 0 ) }, project ).longest, -1 );
}

TEST( Projection, GroundLinesAndRingsInTheImage )
{
  const OrientedImage image( vanCamera(), lookingNorth() );
  const Eigen::Vector3d c = image.exterior().projectionCentre;
  const double groundZ = c.z() - 2.5;
  int looks = 0;
  const GroundPointViewer plain = [&]( const Eigen::Vector3d &g )
  {
    ++looks;
    return GroundPointView { image.projectGroundToPixel( g ), true };
  };
  GroundLineOptions options;
  options.densifyPx = 5.0;

  // a kerb line ahead: one part, densified, every pixel the projection of its ground point, nothing clipped
  const std::vector<Eigen::Vector3d> kerb { { c.x() + 2, c.y() + 6, groundZ }, { c.x() + 2, c.y() + 40, groundZ } };
  const ProjectedGroundLine ahead = projectGroundLine( image, kerb, plain, options );
  ASSERT_EQ( ahead.parts.size(), 1u );
  EXPECT_FALSE( ahead.clipped );
  EXPECT_FALSE( ahead.behind );
  EXPECT_GT( ahead.parts[0].size(), 2u );
  EXPECT_LT( ( ahead.parts[0].front() - image.projectGroundToPixel( kerb.front() ).pixelInImage ).norm(), 1e-9 );
  EXPECT_LT( ( ahead.parts[0].back() - image.projectGroundToPixel( kerb.back() ).pixelInImage ).norm(), 1e-9 );
  for ( size_t i = 1; i < ahead.parts[0].size(); ++i )
    EXPECT_LE( ( ahead.parts[0][i] - ahead.parts[0][i - 1] ).norm(), 5.0 + 1e-9 );
  EXPECT_NEAR( ahead.minDepthM, image.projectGroundToPixel( kerb.front() ).depthM, 1e-9 );

  // the same kerb from 15 m behind the van: cut where it leaves the projectable space, the part ahead kept
  const std::vector<Eigen::Vector3d> through { { c.x() + 2, c.y() - 15, groundZ }, { c.x() + 2, c.y() + 40, groundZ } };
  const ProjectedGroundLine cut = projectGroundLine( image, through, plain, options );
  ASSERT_EQ( cut.parts.size(), 1u );
  EXPECT_TRUE( cut.clipped );
  EXPECT_TRUE( cut.behind );
  EXPECT_FALSE( cut.allInFrame );
  EXPECT_LT( ( cut.parts[0].back() - ahead.parts[0].back() ).norm(), 1e-9 );

  // a ring around the van: clipped in 3-D, closed, every vertex projected
  options.closed = true;
  const std::vector<Eigen::Vector3d> around { { c.x() - 20, c.y() - 15, groundZ }, { c.x() + 20, c.y() - 15, groundZ },
    { c.x() + 20, c.y() + 40, groundZ }, { c.x() - 20, c.y() + 40, groundZ } };
  const ProjectedGroundLine ring = projectGroundLine( image, around, plain, options );
  ASSERT_EQ( ring.parts.size(), 1u );
  EXPECT_TRUE( ring.clipped );
  EXPECT_EQ( ring.parts[0].front(), ring.parts[0].back() );
  EXPECT_GT( ring.minDepthM, 0.0 ); // of the clipped ring, which lies in front
  // and one wholly behind shows nothing
  std::vector<Eigen::Vector3d> behindRing { { c.x() - 2, c.y() - 5, groundZ }, { c.x() + 2, c.y() - 5, groundZ }, { c.x(), c.y() - 9, groundZ } };
  const ProjectedGroundLine gone = projectGroundLine( image, behindRing, plain, options );
  EXPECT_TRUE( gone.parts.empty() );
  EXPECT_FALSE( gone.clipped );
  EXPECT_TRUE( gone.behind );

  // the viewer's occlusion is carried: a terrain that hides everything beyond 20 m
  options.closed = false;
  const GroundPointViewer hiddenFar = [&]( const Eigen::Vector3d &g )
  {
    return GroundPointView { image.projectGroundToPixel( g ), g.y() < c.y() + 20 };
  };
  EXPECT_FALSE( projectGroundLine( image, kerb, hiddenFar, options ).allVisible );
  EXPECT_TRUE( projectGroundLine( image, { kerb.front(), { c.x() + 2, c.y() + 15, groundZ } }, hiddenFar, options ).allVisible );
  options.densifyPx = 0.0;
  EXPECT_THROW( projectGroundLine( image, kerb, plain, options ), std::invalid_argument );
  EXPECT_GT( looks, 0 );
}
