//! The file writers of a run: the history and energy files ([`history::Recorder`], also the
//! in-memory history), `response.npy` ([`response::ResponseFile`]) and their parts of a
//! restart checkpoint. The restart file itself is [`super::restart`].

pub mod columns;
pub mod history;
pub mod history_part;
pub mod response;
