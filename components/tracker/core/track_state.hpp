#pragma once
// The tracker's state and the side the ball was last seen on: declared once here, for the
// tracker core and for the motion controller core that acts on them (header only, no Eigen).

namespace stereoball::tracker {

/// Tracker state (IDL TrackState).
enum class TrackState { kIdle, kFollowing, kSearching };

/// Side of the image where the ball was last seen (IDL Side).
enum class Side { kUnknown, kLeft, kRight };

}  // namespace stereoball::tracker
