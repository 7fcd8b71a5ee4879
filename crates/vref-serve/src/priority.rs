//! The solver thread gives way to the query path: on a 2-core machine a
//! solve that holds a core would otherwise delay the answers, the feeds
//! and the clients queued behind it. A nicer thread still has a whole
//! core whenever nothing else wants one.

/// Sets the calling thread's nice value (Linux keeps one per thread).
pub fn set_this_thread_nice(nice: i32) -> std::io::Result<()> {
    let tid = nix::unistd::gettid().as_raw();
    let who = libc::id_t::try_from(tid).map_err(std::io::Error::other)?;
    // SAFETY: setpriority reads only its three integer arguments and
    // changes the scheduling of thread `who`, this thread; it touches no
    // memory of ours.
    #[allow(unsafe_code)]
    let result = unsafe { libc::setpriority(libc::PRIO_PROCESS, who, nice) };
    if result == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nice_of_this_thread() -> i32 {
        // SAFETY: getpriority reads only its integer arguments.
        #[allow(unsafe_code)]
        let nice = unsafe { libc::getpriority(libc::PRIO_PROCESS, 0) };
        nice
    }

    #[test]
    fn a_thread_can_make_itself_nicer_without_touching_the_others() {
        let before = nice_of_this_thread();
        let niced = std::thread::spawn(|| {
            set_this_thread_nice(19)?;
            Ok::<_, std::io::Error>(nice_of_this_thread())
        });
        assert_eq!(niced.join().ok().and_then(Result::ok), Some(19));
        assert_eq!(nice_of_this_thread(), before);
    }
}
