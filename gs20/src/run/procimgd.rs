// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd's side of the bridge: its station's services (the notifications, defining and
//! releasing the station) and its image (the I data the bridge writes, the Q data it
//! reads), for a station its program defines.

use crate::run::definition;
use crate::run::image::{ImageMap, LayoutMismatch};
use procimg_client::{
    AttachOptions, Client, ControlError, Event, IoError, Ioxs, ServiceOptions, Services,
    StatusReport,
};
use procimg_gs20::link::{ItemSlot, Station};
use std::os::fd::RawFd;
use std::time::{Duration, Instant};

/// How the bridge names itself to procimgd (`procimg status`: "defined by procimg-gs20").
pub const CLIENT_NAME: &str = "procimg-gs20";

/// How long procimgd may take to run a defined station (a new generation, the client
/// re-attached): generous, a loaded machine is slow, not wrong.
pub const START_WAIT: Duration = Duration::from_secs(20);

/// Why the bridge cannot work with the instance.
#[derive(Debug, thiserror::Error)]
pub enum AttachError {
    /// Opening the services or the image failed.
    #[error("cannot attach to procimgd instance \"{instance}\": {cause}")]
    Attach {
        /// The instance.
        instance: String,
        /// Why.
        cause: procimg_client::AttachError,
    },
    /// The status request failed.
    #[error("procimgd instance \"{instance}\" does not tell its status: {cause}")]
    Status {
        /// The instance.
        instance: String,
        /// Why.
        cause: ControlError,
    },
    /// A controller.
    #[error(
        "procimgd instance \"{instance}\" is an IO controller (role \"{role}\"); procimg-gs20 \
         needs the IO device role: role = \"device\" with [station] gsdml = \"FILE\" and no \
         [[station.submodule]]"
    )]
    NotDevice {
        /// The instance.
        instance: String,
        /// Its role.
        role: String,
    },
    /// A station with configured submodules.
    #[error(
        "the station of procimgd instance \"{instance}\" is configured with its submodules; \
         for procimg-gs20 the host's items define it: configure [station] gsdml = \"FILE\" \
         (written by `procimg-gs20 gsdml -o FILE`) and no [[station.submodule]]"
    )]
    Configured {
        /// The instance.
        instance: String,
    },
    /// Another program defined the station.
    #[error(
        "the station of procimgd instance \"{instance}\" is defined by {by} already; stop \
         that program (or that procimg-gs20) first"
    )]
    Taken {
        /// The instance.
        instance: String,
        /// The program.
        by: String,
    },
}

/// Why the host's station did not start.
#[derive(Debug, thiserror::Error)]
pub enum StartError {
    /// procimgd refused the tree or the identity.
    #[error(
        "procimgd instance \"{instance}\" did not take the host's station: {cause}; every \
         item must be a module of the station's GSDML file (`procimg-gs20 gsdml -o FILE` \
         writes one with the whole catalogue), the host name a NameOfStation"
    )]
    Refused {
        /// The instance.
        instance: String,
        /// Why.
        cause: ControlError,
    },
    /// procimgd did not run it in time.
    #[error(
        "procimgd instance \"{instance}\" took the host's station but did not run it within \
         {} s; see procimgd's log",
        START_WAIT.as_secs()
    )]
    Timeout {
        /// The instance.
        instance: String,
    },
    /// procimgd runs another station.
    #[error(transparent)]
    Layout(#[from] LayoutMismatch),
    /// Claiming the I data failed.
    #[error("cannot claim the I data of procimgd instance \"{instance}\": {cause}")]
    Claim {
        /// The instance.
        instance: String,
        /// Why.
        cause: ControlError,
    },
}

/// A definition waiting for procimgd to run it.
#[derive(Clone, Debug)]
pub struct Starting {
    /// The data client's generation before the definition.
    before: u64,
    items: Vec<ItemSlot>,
    deadline: Instant,
}

/// procimgd's instance, attached.
pub struct Procimgd {
    instance: String,
    // The client before the services: neither's drop order matters to the server, but the
    // services' handle is the station's program and goes last.
    client: Client,
    services: Services,
}

impl Procimgd {
    /// Attaches to `instance`, which must be the device role with a station its program
    /// defines, waiting for one.
    pub fn attach(instance: &str) -> Result<Procimgd, AttachError> {
        let attach = |cause| AttachError::Attach {
            instance: instance.to_owned(),
            cause,
        };
        let services =
            Services::open(instance, ServiceOptions::new(CLIENT_NAME)).map_err(attach)?;
        let status = services
            .control()
            .status()
            .map_err(|cause| AttachError::Status {
                instance: instance.to_owned(),
                cause,
            })?;
        let Some(station) = status.station else {
            return Err(AttachError::NotDevice {
                instance: instance.to_owned(),
                role: status.role,
            });
        };
        let Some(program) = station.program else {
            return Err(AttachError::Configured {
                instance: instance.to_owned(),
            });
        };
        if let Some(by) = program.defined_by {
            return Err(AttachError::Taken {
                instance: instance.to_owned(),
                by,
            });
        }
        let client =
            Client::attach(instance, AttachOptions::asynchronous(CLIENT_NAME)).map_err(attach)?;
        Ok(Procimgd {
            instance: instance.to_owned(),
            client,
            services,
        })
    }

    /// The station's services (its notifications).
    pub fn services(&mut self) -> &mut Services {
        &mut self.services
    }

    /// The status, asked now.
    pub fn status(&self) -> Result<StatusReport, ControlError> {
        self.services.control().status()
    }

    /// The descriptor that becomes readable when notifications arrive.
    pub fn notify_fd(&self) -> RawFd {
        self.services.notify_fd()
    }

    /// The descriptor that becomes readable each cycle (a new image), while attached.
    pub fn image_fd(&self) -> Option<RawFd> {
        self.client.event_fd()
    }

    /// Takes the newest image and the client's events (re-attaching to a new server when
    /// its time comes); whether the client is attached to a live server.
    pub fn drive(&mut self) -> (bool, Vec<Event>) {
        let _ = self.client.newest_inputs();
        let events = self.client.events();
        (self.client.connected(), events)
    }

    /// Defines the host's station; [`poll_start`](Self::poll_start) says when it runs.
    pub fn define(&mut self, station: &Station) -> Result<Starting, StartError> {
        let before = self.client.generation();
        self.services
            .define_station_as(&definition::tree(station), &definition::identity(station))
            .map_err(|cause| StartError::Refused {
                instance: self.instance.clone(),
                cause,
            })?;
        Ok(Starting {
            before,
            items: station.items.clone(),
            deadline: Instant::now() + START_WAIT,
        })
    }

    /// Whether the defined station runs: the client re-attached to procimgd's new
    /// generation, whose layout has the host's items; then the I data is claimed and the
    /// image map returned.
    pub fn poll_start(
        &mut self,
        s: &Starting,
        now: Instant,
    ) -> Result<Option<ImageMap>, StartError> {
        let instance = self.instance.clone();
        let timeout = || StartError::Timeout { instance };
        let (up, _) = self.drive();
        if !up || self.client.generation() == s.before {
            return if now >= s.deadline {
                Err(timeout())
            } else {
                Ok(None)
            };
        }
        let map = match ImageMap::new(self.client.layout(), &s.items) {
            Ok(map) => map,
            // A generation in between is not the defined station: after a Request Reset
            // and a Request Start back to back, the waiting station of the release runs
            // first. The layout is wrong only once the defined station runs.
            Err(e) if self.runs_defined() => return Err(e.into()),
            Err(_) if now >= s.deadline => return Err(timeout()),
            Err(_) => return Ok(None),
        };
        self.client
            .claim_i_data()
            .map_err(|cause| StartError::Claim {
                instance: self.instance.clone(),
                cause,
            })?;
        Ok(Some(map))
    }

    /// Whether the generation the client is attached to runs a defined station.
    fn runs_defined(&self) -> bool {
        self.status().is_ok_and(|st| {
            st.generation == self.client.generation()
                && st
                    .station
                    .and_then(|s| s.program)
                    .is_some_and(|p| p.defined_by.is_some())
        })
    }

    /// Writes the host's input image as the station's I data, all submodules in one sample
    /// (applied in one cycle: the PLC never sees a torn image), with `status` as their IOPS.
    pub fn write_inputs(
        &mut self,
        map: &ImageMap,
        inputs: &[u8],
        status: Ioxs,
    ) -> Result<(), IoError> {
        for (_, address, part) in map.input_parts(inputs) {
            self.client.data_write_cache(address, part, status)?;
        }
        self.client.data_write_cache_flush()
    }

    /// The host's output image from the newest image.
    pub fn read_outputs(&mut self, map: &ImageMap) -> Option<Vec<u8>> {
        let payload = self.client.newest_inputs().ok()?;
        map.outputs(payload)
    }

    /// Ends the bridge's part as the station's program: the AR ends, the station waits off
    /// the wire.
    pub fn release(&self) -> Result<(), ControlError> {
        self.services.release_station()
    }

    /// The generation of the procimgd the data client is attached to.
    pub fn generation(&self) -> u64 {
        self.client.generation()
    }

    /// The instance's name.
    pub fn instance(&self) -> &str {
        &self.instance
    }
}
