//! The type every loader of the crate returns. A leaf, so that the resolver
//! ([`crate::source`]) and the formats it resolves to ([`crate::fits`], [`crate::convert`])
//! share it without depending on each other.

use specula_core::Brdf;
use std::sync::Arc;

/// A loaded BRDF behind a shared pointer, so that parallel work can hold it.
pub type BrdfSource = Arc<dyn Brdf>;
