// SPDX-License-Identifier: MIT OR Apache-2.0
//! What clients ask the server, split by who answers it: the core requests the control side
//! answers for either role ([`CoreRequest`]), the IO controller's services
//! ([`ControllerRequest`]) and the IO device's station services ([`DeviceRequest`]). Each
//! role's services take only their own requests; the control side refuses a request of the
//! other role before it reaches them.
//!
//! On the wire all three are one JSON object tagged by `"request"`, as they always were: a
//! client does not say which group a request belongs to, the tag does.

mod controller;
mod core;
mod device;

pub use self::core::{ClientRole, CoreRequest, RestartClients};
pub use controller::{ControllerRequest, Tailoring};
pub use device::{DefinedIdentity, DeviceRequest, StationAlarmKind, StationTreeEntry, TreeRecords};

use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize};

/// A request from a client, in the group that answers it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(untagged)]
pub enum Request {
    /// Answered by the control side for either role.
    Core(CoreRequest),
    /// Answered by a server in the IO controller role.
    Controller(ControllerRequest),
    /// Answered by a server in the IO device role.
    Device(DeviceRequest),
}

impl From<CoreRequest> for Request {
    fn from(r: CoreRequest) -> Request {
        Request::Core(r)
    }
}

impl From<ControllerRequest> for Request {
    fn from(r: ControllerRequest) -> Request {
        Request::Controller(r)
    }
}

impl From<DeviceRequest> for Request {
    fn from(r: DeviceRequest) -> Request {
        Request::Device(r)
    }
}

/// serde's message for a tag an enum does not have (`Error::unknown_variant`).
const UNKNOWN_VARIANT: &str = "unknown variant";

impl<'de> Deserialize<'de> for Request {
    /// Offers the message to each group in turn. A group that does not know the tag passes it
    /// on; one that knows it keeps it, so a request with a wrong field is refused with what is
    /// wrong with it, not with "matches no group".
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Request, D::Error> {
        let value = serde_json::Value::deserialize(d)?;
        let unknown = |e: &serde_json::Error| e.to_string().starts_with(UNKNOWN_VARIANT);
        match CoreRequest::deserialize(&value) {
            Ok(r) => return Ok(Request::Core(r)),
            Err(e) if !unknown(&e) => return Err(D::Error::custom(e)),
            Err(_) => {}
        }
        match ControllerRequest::deserialize(&value) {
            Ok(r) => return Ok(Request::Controller(r)),
            Err(e) if !unknown(&e) => return Err(D::Error::custom(e)),
            Err(_) => {}
        }
        match DeviceRequest::deserialize(&value) {
            Ok(r) => Ok(Request::Device(r)),
            Err(e) if !unknown(&e) => Err(D::Error::custom(e)),
            Err(_) => Err(D::Error::custom(format!(
                "unknown request {}: this server does not know it (a newer client?)",
                value.get("request").unwrap_or(&serde_json::Value::Null)
            ))),
        }
    }
}

#[cfg(test)]
mod tests;
