//! Connection set-up: where the samples come from ([`Source`]), the device reached before
//! the journal is opened, and the instrument with its calibration (the journal's, once
//! there is one): the simulator calibrated on it, or a remote device with the calibration
//! it was given.

use crate::ideal::{exact_calibration, NoiselessSimulator};
use crate::journal::{Journal, MeasureSettings, SourceRecord};
use crate::observer::Observer;
use crate::pace::Paced;
use crate::protocol::validate::ReplyRanges;
use crate::protocol::{ClientSettings, Endpoint, RemoteInstrument};
use crate::workflow_error::WorkflowError;
use specula_acquisition::calibration::response::{measure_response, ResponseFit, ResponseOptions};
use specula_acquisition::calibration::{
    calibrate, mount_by_device, Calibration, CalibrationOptions,
};
use specula_acquisition::device::Device;
use specula_acquisition::hdr::{HdrCapturer, HdrSettings};
use specula_acquisition::instrument::{Instrument, InstrumentInfo};
use specula_acquisition::response::InstrumentResponse;
use specula_acquisition::simulator::sample::{MountedSample, Tilt};
use specula_acquisition::simulator::{Simulator, SimulatorConfig};
use specula_core::Brdf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Where the samples come from.
pub enum Source {
    /// The simulated device with a ground-truth BRDF.
    Simulated {
        /// The BRDF the simulated device measures.
        truth: Arc<dyn Brdf>,
        /// Runs the simulated clock in real time divided by this (rehearsals, tests).
        speedup: Option<f64>,
    },
    /// A device behind the driver protocol, with its calibration.
    Remote {
        /// Where the device's driver listens.
        endpoint: Endpoint,
        /// How the connection waits, retries and authenticates, and the ranges replies must lie in.
        client: ClientSettings,
        /// The device's calibration (`specula calibrate`).
        calibration: Box<Calibration>,
    },
}

/// A source whose device has answered: a remote device is reached before the journal is
/// opened, so that a failed connection leaves no session behind.
pub(crate) enum Reached {
    Simulated {
        truth: Arc<dyn Brdf>,
        speedup: Option<f64>,
    },
    Remote {
        remote: Box<RemoteInstrument>,
        calibration: Box<Calibration>,
    },
}

impl Reached {
    /// Reaches the device; a remote device's waits end early once `stop` is raised.
    pub(crate) fn reach(
        source: Source,
        device: &Device,
        settings: &MeasureSettings,
        stop: &Arc<AtomicBool>,
    ) -> Result<Self, WorkflowError> {
        Ok(match source {
            Source::Simulated { truth, speedup } => Reached::Simulated { truth, speedup },
            Source::Remote {
                endpoint,
                client,
                calibration,
            } => {
                if settings.ideal {
                    return Err(WorkflowError::IdealRemote { endpoint });
                }
                let client = ClientSettings {
                    ranges: ReplyRanges::for_device(device),
                    ..client
                };
                let mut remote =
                    RemoteInstrument::new(endpoint.clone(), client).with_stop(stop.clone());
                remote.info().map_err(|cause| WorkflowError::Unreachable {
                    endpoint: endpoint.clone(),
                    cause,
                })?;
                Reached::Remote {
                    remote: Box::new(remote),
                    calibration,
                }
            }
        })
    }
}

/// What the journal records as the measured thing: the simulated truth's name, or the
/// device's own identity from its info reply (not its address, which may change).
pub(crate) fn describe(truth: Option<String>, info: &InstrumentInfo) -> SourceRecord {
    match truth {
        Some(truth) => SourceRecord::Simulated { truth },
        None => SourceRecord::Device {
            model: info.model.clone(),
            serial: info.serial.clone(),
        },
    }
}

/// The instrument and what goes with it.
pub(crate) struct Connected {
    pub(crate) instrument: Box<dyn Instrument>,
    pub(crate) calibration: Calibration,
    pub(crate) link_notes: Option<crate::protocol::client::LinkNotes>,
    pub(crate) simulated: bool,
    /// The name the device gave in `hello` (a remote device only).
    pub(crate) server: Option<String>,
}

/// Opens the instrument and finds its calibration (the journal's, once there is one).
pub(crate) fn connect(
    source: Reached,
    device: &Device,
    settings: &MeasureSettings,
    journal: &Journal,
    stop: &Arc<AtomicBool>,
    observer: &mut dyn Observer,
) -> Result<Connected, WorkflowError> {
    match source {
        Reached::Simulated { truth, speedup } => {
            let mut config = SimulatorConfig::new(settings.seed, device);
            if settings.point_light {
                config.response =
                    InstrumentResponse::point(device.light.distance_m, device.camera.distance_m);
            }
            let tilt = if settings.ideal {
                config.positioning.sigma_deg = 0.0;
                Tilt::default()
            } else {
                Tilt::new(settings.tilt_deg, settings.tilt_azimuth_deg)
            };
            let sample = MountedSample::new(truth.name(), truth, tilt);
            let true_response = config.response.clone();
            let mut simulator = Simulator::new(device.clone(), sample.clone(), config);
            let calibration = match journal.record::<Calibration>()? {
                Some(stored) => stored,
                None => {
                    let calibration = if settings.ideal {
                        let model = simulator.info()?.model;
                        let mut c = exact_calibration(&simulator.config().camera, &model);
                        c.response = Some(ResponseFit::exact(true_response));
                        c
                    } else {
                        observer.step("calibrating: white reference and ColorChecker");
                        let mut c = calibrate(
                            &mut simulator,
                            mount_by_device,
                            &CalibrationOptions::default(),
                        )
                        .map_err(|cause| WorkflowError::Calibration { cause })?;
                        c.response = Some(if settings.point_light {
                            ResponseFit::exact(true_response)
                        } else {
                            observer.step("calibrating: the response, a mirror across the light");
                            simulated_response(&mut simulator, &c, device)?
                        });
                        simulator.mount_sample(sample);
                        c
                    };
                    journal.put_record(&calibration)?;
                    calibration
                }
            };
            let instrument: Box<dyn Instrument> = match (settings.ideal, speedup) {
                (true, Some(s)) => Box::new(
                    Paced::new(NoiselessSimulator::new(simulator), s).with_stop(stop.clone()),
                ),
                (true, None) => Box::new(NoiselessSimulator::new(simulator)),
                (false, Some(s)) => Box::new(Paced::new(simulator, s).with_stop(stop.clone())),
                (false, None) => Box::new(simulator),
            };
            Ok(Connected {
                instrument,
                calibration,
                link_notes: None,
                simulated: true,
                server: None,
            })
        }
        Reached::Remote {
            remote,
            calibration,
        } => {
            let calibration = *calibration;
            let stored: Calibration = journal.record_or_insert(|| calibration.clone())?;
            if stored != calibration {
                return Err(WorkflowError::Calibrated {
                    session: journal.path().to_path_buf(),
                });
            }

            let notes = remote.notes();
            let simulated = remote.simulated_clock_s().is_some();
            let server = remote.server_name().map(str::to_string);
            Ok(Connected {
                instrument: remote,
                calibration,
                link_notes: Some(notes),
                simulated,
                server,
            })
        }
    }
}

/// The response measured on the simulator with the reference mirror
/// ([`measure_response`]).
pub fn simulated_response(
    simulator: &mut Simulator,
    calibration: &Calibration,
    device: &Device,
) -> Result<ResponseFit, WorkflowError> {
    let info = simulator.info()?;
    let mut hdr = HdrCapturer::new(HdrSettings::for_device(&info), calibration.noise);
    measure_response(
        simulator,
        mount_by_device,
        &mut hdr,
        calibration,
        &device.response(),
        &ResponseOptions::default(),
    )
    .map_err(|cause| WorkflowError::Response { cause })
}
