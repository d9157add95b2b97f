/***************************************************************************
  crs.cpp - checks on a block's coordinate reference system
 ***************************************************************************/
#include "geometry/crs.h"

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include <proj.h>

namespace geostation
{

  namespace
  {
    struct ContextDeleter
    {
      void operator()( PJ_CONTEXT *ctx ) const { proj_context_destroy( ctx ); }
    };
    struct PjDeleter
    {
      void operator()( PJ *pj ) const { proj_destroy( pj ); }
    };
    using ContextPtr = std::unique_ptr<PJ_CONTEXT, ContextDeleter>;
    using PjPtr = std::unique_ptr<PJ, PjDeleter>;

    std::string kindOf( PJ_TYPE type )
    {
      switch ( type )
      {
        case PJ_TYPE_PROJECTED_CRS:
          return "projected";
        case PJ_TYPE_ENGINEERING_CRS:
          return "engineering";
        case PJ_TYPE_GEOGRAPHIC_2D_CRS:
        case PJ_TYPE_GEOGRAPHIC_3D_CRS:
        case PJ_TYPE_GEOGRAPHIC_CRS:
          return "geographic";
        case PJ_TYPE_GEOCENTRIC_CRS:
          return "geocentric";
        case PJ_TYPE_VERTICAL_CRS:
          return "vertical";
        case PJ_TYPE_BOUND_CRS:
          return "bound";
        default:
          return "other";
      }
    }

    bool threeDimensional( PJ_TYPE type )
    {
      return type == PJ_TYPE_GEOGRAPHIC_3D_CRS || type == PJ_TYPE_GEOCENTRIC_CRS || type == PJ_TYPE_COMPOUND_CRS;
    }

    //! The vertical CRS of a compound CRS (a bound one unwrapped), or nothing.
    PjPtr verticalPart( PJ_CONTEXT *ctx, PJ *crs )
    {
      PjPtr bare( proj_get_type( crs ) == PJ_TYPE_BOUND_CRS ? proj_get_source_crs( ctx, crs ) : proj_clone( ctx, crs ) );
      if ( !bare || proj_get_type( bare.get() ) != PJ_TYPE_COMPOUND_CRS )
        return nullptr;
      return PjPtr( proj_crs_get_sub_crs( ctx, bare.get(), 1 ) );
    }

    /**
     * Whether PROJ can bring heights from `from` (3-D) to the vertical CRS of `to` by more than
     * a ballpark (heights passed through unchanged): the geoid model it needs is installed.
     */
    bool heightsReachable( PJ_CONTEXT *ctx, PJ *from, PJ *to )
    {
      PJ_OPERATION_FACTORY_CONTEXT *factory = proj_create_operation_factory_context( ctx, nullptr );
      if ( !factory )
        return false;
      proj_operation_factory_context_set_grid_availability_use( ctx, factory, PROJ_GRID_AVAILABILITY_DISCARD_OPERATION_IF_MISSING_GRID );
      proj_operation_factory_context_set_spatial_criterion( ctx, factory, PROJ_SPATIAL_CRITERION_PARTIAL_INTERSECTION );
      PJ_OBJ_LIST *operations = proj_create_operations( ctx, from, to, factory );
      bool reachable = false;
      for ( int i = 0; operations && i < proj_list_get_count( operations ) && !reachable; ++i )
      {
        PjPtr operation( proj_list_get( ctx, operations, i ) );
        reachable = operation && !proj_coordoperation_has_ballpark_transformation( ctx, operation.get() );
      }
      proj_list_destroy( operations );
      proj_operation_factory_context_destroy( factory );
      return reachable;
    }
  } // namespace

  CrsDescription describeCrs( const std::string &definition )
  {
    ContextPtr ctx( proj_context_create() );
    proj_log_level( ctx.get(), PJ_LOG_NONE );
    PjPtr crs( proj_create( ctx.get(), definition.c_str() ) );
    if ( !crs || !proj_is_crs( crs.get() ) )
      throw std::invalid_argument( "'" + definition + "' is not a coordinate reference system PROJ recognises" );

    // A bound CRS (with +towgs84) wraps the real one; a compound CRS has its
    // horizontal part first.
    if ( proj_get_type( crs.get() ) == PJ_TYPE_BOUND_CRS )
      crs.reset( proj_get_source_crs( ctx.get(), crs.get() ) );
    if ( crs && proj_get_type( crs.get() ) == PJ_TYPE_COMPOUND_CRS )
      crs.reset( proj_crs_get_sub_crs( ctx.get(), crs.get(), 0 ) );
    if ( crs && proj_get_type( crs.get() ) == PJ_TYPE_BOUND_CRS )
      crs.reset( proj_get_source_crs( ctx.get(), crs.get() ) );
    if ( !crs )
      throw std::invalid_argument( "'" + definition + "' has no horizontal coordinate reference system" );

    CrsDescription description;
    const char *name = proj_get_name( crs.get() );
    description.name = name ? name : definition;
    description.kind = kindOf( proj_get_type( crs.get() ) );

    PjPtr cs( proj_crs_get_coordinate_system( ctx.get(), crs.get() ) );
    if ( cs && proj_cs_get_axis_count( ctx.get(), cs.get() ) > 0 )
    {
      const char *unitName = nullptr;
      double toSi = 0.0;
      if ( proj_cs_get_axis_info( ctx.get(), cs.get(), 0, nullptr, nullptr, nullptr, &toSi, &unitName, nullptr, nullptr ) )
      {
        description.unitName = unitName ? unitName : "";
        description.unitToMetre = toSi;
      }
    }
    return description;
  }

  std::string verticalCrsName( const std::string &definition )
  {
    ContextPtr ctx( proj_context_create() );
    proj_log_level( ctx.get(), PJ_LOG_NONE );
    PjPtr crs( proj_create( ctx.get(), definition.c_str() ) );
    if ( !crs || !proj_is_crs( crs.get() ) )
      throw std::invalid_argument( "'" + definition + "' is not a coordinate reference system PROJ recognises" );
    const PjPtr vertical = verticalPart( ctx.get(), crs.get() );
    const char *name = vertical ? proj_get_name( vertical.get() ) : nullptr;
    return name ? name : "";
  }

  void requireProjectedMetricCrs( const std::string &definition )
  {
    const CrsDescription d = describeCrs( definition );
    if ( d.kind == "geographic" )
      throw std::invalid_argument( "'" + definition + "' (" + d.name + ") is a geographic CRS in degrees; a block needs a projected CRS in metres (e.g. the UTM zone of the survey)" );
    if ( d.kind != "projected" && d.kind != "engineering" )
      throw std::invalid_argument( "'" + definition + "' (" + d.name + ") is a " + d.kind + " CRS; a block needs a projected or local engineering CRS in metres" );
    if ( std::abs( d.unitToMetre - 1.0 ) > 1e-12 )
      throw std::invalid_argument( "'" + definition + "' (" + d.name + ") has axes in " + ( d.unitName.empty() ? std::string( "unknown units" ) : d.unitName ) + "; a block needs a CRS in metres" );
  }

  CrsTransform::CrsTransform( const std::string &from, const std::string &to )
  {
    PJ_CONTEXT *ctx = proj_context_create();
    proj_log_level( ctx, PJ_LOG_NONE );
    mContext = ctx;
    PJ *a = proj_create( ctx, from.c_str() ), *b = proj_create( ctx, to.c_str() );
    if ( !a || !b )
    {
      proj_destroy( a );
      proj_destroy( b );
      proj_context_destroy( ctx );
      mContext = nullptr;
      throw std::invalid_argument( "a CRS PROJ does not recognise: '" + ( a ? to : from ) + "'" );
    }
    mIdentity = proj_is_equivalent_to( a, b, PJ_COMP_EQUIVALENT );
    // heights with a datum (ellipsoidal, geocentric) into a vertical datum: never passed through unchanged
    // because the geoid model is missing (PROJ would fall back to a ballpark without a word)
    std::string verticalName;
    if ( !mIdentity && threeDimensional( proj_get_type( a ) ) )
      if ( PjPtr vertical = verticalPart( ctx, b ) )
        if ( !heightsReachable( ctx, a, b ) )
          verticalName = proj_get_name( vertical.get() ) ? proj_get_name( vertical.get() ) : to;
    proj_destroy( a );
    proj_destroy( b );
    if ( !verticalName.empty() )
    {
      proj_context_destroy( ctx );
      mContext = nullptr;
      throw std::invalid_argument( "heights cannot be brought into " + verticalName + ": PROJ knows no way there but a ballpark that leaves them unchanged "
                                   "(the geoid model it needs is not installed: add its grid, e.g. with projsync, or give a CRS without a vertical datum to keep ellipsoidal heights)" );
    }
    if ( mIdentity )
      return;
    PJ *raw = proj_create_crs_to_crs( ctx, from.c_str(), to.c_str(), nullptr );
    PJ *normalised = raw ? proj_normalize_for_visualization( ctx, raw ) : nullptr;
    proj_destroy( raw );
    if ( !normalised )
    {
      proj_context_destroy( ctx );
      mContext = nullptr;
      throw std::invalid_argument( "PROJ finds no transformation between the two CRSs" );
    }
    mTransform = normalised;
  }

  CrsTransform::~CrsTransform()
  {
    proj_destroy( static_cast<PJ *>( mTransform ) );
    if ( mContext )
      proj_context_destroy( static_cast<PJ_CONTEXT *>( mContext ) );
  }

  Eigen::Vector3d CrsTransform::transform( const Eigen::Vector3d &point ) const
  {
    if ( mIdentity )
      return point;
    const PJ_COORD out = proj_trans( static_cast<PJ *>( mTransform ), PJ_FWD, proj_coord( point.x(), point.y(), point.z(), 0.0 ) );
    if ( out.xyz.x == HUGE_VAL )
      return Eigen::Vector3d::Constant( std::numeric_limits<double>::quiet_NaN() );
    return { out.xyz.x, out.xyz.y, out.xyz.z };
  }

} // namespace geostation
