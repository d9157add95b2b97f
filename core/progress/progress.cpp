/***************************************************************************
  progress.cpp - what a long operation reports while it runs, and asks
 ***************************************************************************/
#include "progress/progress.h"

#include <algorithm>
#include <stdexcept>

namespace geostation
{

  Progress::Progress( Report report, StopQuery stop )
  {
    auto hooks = std::make_shared<Hooks>();
    hooks->report = std::move( report );
    hooks->stop = std::move( stop );
    mHooks = std::move( hooks );
  }

  bool Progress::report( double fraction, const std::string &message ) const
  {
    if ( mHooks && mHooks->report )
      mHooks->report( mFrom + ( mTo - mFrom ) * std::clamp( fraction, 0.0, 1.0 ), message );
    return !stopRequested();
  }

  bool Progress::stopRequested() const
  {
    if ( !mHooks )
      return false;
    if ( !mHooks->stopped.load( std::memory_order_relaxed ) && mHooks->stop && mHooks->stop() )
      mHooks->stopped.store( true, std::memory_order_relaxed );
    return mHooks->stopped.load( std::memory_order_relaxed );
  }

  Progress Progress::part( double from, double to ) const
  {
    if ( !( from >= 0.0 && from <= to && to <= 1.0 ) )
      throw std::invalid_argument( "a part of a progress is a span within 0 to 1" );
    Progress inner = *this;
    inner.mFrom = mFrom + ( mTo - mFrom ) * from;
    inner.mTo = mFrom + ( mTo - mFrom ) * to;
    return inner;
  }

} // namespace geostation
