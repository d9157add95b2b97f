/***************************************************************************
  matchimagecache.h - the images of the last few stations, ready to match
  -------------------------------------------------------------------------
  Reading an image and preparing it for matching (grey values, B-spline
  coefficients) takes tens of milliseconds for a full-HD frame, so the
  Multiview prepares the images of a station while the operator looks at
  it, and keeps the last `capacity` ones, within a memory budget (the most
  recent image always kept: 1 GiB by default, about 55 full-HD frames, or
  the last image alone when it is larger). Safe to use from several
  threads: a second request for an image being loaded waits for the first.

  An image over `maxWholePixels` (64 Mpx by default: 576 MB prepared) is
  never prepared whole: get() only reads its size and says it needs a
  window, and get( path, window ) prepares that window (and a margin) of
  it, keeping the last window of each such image. A 20 000 x 20 000 image
  then costs the windows a measurement reads (measurementWindows()), not
  3.6 GB.
 ***************************************************************************/
#ifndef GEOSTATION_WORKSTATION_MATCHIMAGECACHE_H
#define GEOSTATION_WORKSTATION_MATCHIMAGECACHE_H

#include <condition_variable>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <optional>
#include <string>

#include "matching/matchimage.h"

namespace geostation
{

  class MatchImageCache
  {
    public:
      //! At most `capacity` images and, beyond the most recent one, `maxBytes` of prepared pixels (MatchImage::bytes()).
      explicit MatchImageCache( size_t capacity = 18, size_t maxBytes = size_t( 1 ) << 30, long long maxWholePixels = 64'000'000 );

      //! Bytes of prepared pixels held now.
      size_t bytes() const;

      struct Entry
      {
        enum class Status
        {
          Ready,      //!< prepared (whole, or the window asked for)
          Unreadable, //!< the file cannot be opened or decoded: `message` says why
        };
        Status status = Status::Ready;
        std::string message;                     //!< one sentence when Unreadable
        //! nullptr when Unreadable; for an image too large to prepare whole, the window last read of it (or nullptr)
        std::shared_ptr<const MatchImage> image;
        cv::Size imageSize { 0, 0 };             //!< the whole image's (pixels), when it could be opened
        bool needsWindow = false;                //!< too large to prepare whole: ask for a window of it
        bool ok() const { return status == Status::Ready; }
      };

      /**
       * The prepared image of a file, read on first use. An error is
       * remembered while the file stays as it was (missing, or the same
       * size and time): a file put back or rewritten is read again.
       */
      Entry get( const std::string &path );

      /**
       * The same; for an image too large to prepare whole, a window holding
       * the pixels `window` (image pixels, clipped to the image): the one
       * kept if it holds them, else read now. Throws std::invalid_argument
       * for a window over maxWholePixels.
       */
      Entry get( const std::string &path, const cv::Rect &window );

      //! Whether the file is prepared already (no reading).
      bool contains( const std::string &path ) const;

      void clear();

      long long maxWholePixels() const { return mMaxWholePixels; }

    private:
      Entry fetch( const std::string &path, const std::optional<cv::Rect> &window );
      Entry read( const std::string &path, const std::optional<cv::Rect> &window ) const;

      size_t mCapacity;
      size_t mMaxBytes;
      long long mMaxWholePixels;
      size_t mBytes = 0;
      mutable std::mutex mMutex;
      std::condition_variable mLoaded;
      std::set<std::string> mLoading;
      std::list<std::string> mOrder; //!< most recent first
      std::map<std::string, Entry> mEntries;
      std::map<std::string, std::string> mErrorStamps; //!< the file's state (fileStamp()) when its error was remembered
  };

} // namespace geostation

#endif // GEOSTATION_WORKSTATION_MATCHIMAGECACHE_H
