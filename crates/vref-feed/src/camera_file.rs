//! What a camera file (`camera.json`) held that vref did not read, said
//! where vref reads frame folders: `vref match`, `vref segment`, the
//! `rgbd:` sources.

/// Says, at warn, the keys of `who`'s camera file that were not read
/// (`vref_perception::folder::Camera::read`): a misspelt key leaves its
/// default, which nothing else would show.
pub fn warn_unread(unread: &[String], who: &str) {
    if !unread.is_empty() {
        tracing::warn!(
            frame = who,
            "camera file keys not read: {} (read: {})",
            unread.join(", "),
            vref_perception::folder::CAMERA_KEYS
        );
    }
}
