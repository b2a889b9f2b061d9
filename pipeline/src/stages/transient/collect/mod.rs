//! Data-only sinks: what a run collects for its verdict, in memory — the response
//! ([`response::Response`]), the contact's validity ([`contact::ContactMonitor`]), the rotor
//! face's normal velocity ([`face::FaceMonitor`]) and the BDF's steps by order
//! ([`orders::OrderTally`]). They write no file; the verdict reads what they hold.

pub mod contact;
pub mod face;
pub mod orders;
pub mod response;
