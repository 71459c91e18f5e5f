// SPDX-License-Identifier: MIT OR Apache-2.0
//! The output frame as the cycle sends it: from the image, where the cycle put the outputs,
//! with its header and status written around them; written whole from the image when the
//! AR's frame is not the one the image holds.

use super::test_rig::{CONTROLLER, Rig, at};
use super::{FromImage, PnioIo};
use crate::io::IoSystem;
use procimg_nic::{Nic, RecvError, SendError};
use procimg_profinet::cyclic::CyclicAr;
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::rt::data_status;
use procimg_shm_layout::{IOXS_GOOD, Mode, SubmoduleStatus};

/// A device with two output submodules around an input one.
const OUTPUTS: &str = r#"
    [[device]]
    name = "io"
    vendor_id = 1
    device_id = 1
    [[device.submodule]]
    slot = 1
    subslot = 1
    module_ident = 1
    submodule_ident = 1
    output_length = 6
    [[device.submodule]]
    slot = 2
    subslot = 1
    module_ident = 2
    submodule_ident = 2
    input_length = 2
    [[device.submodule]]
    slot = 3
    subslot = 1
    module_ident = 3
    submodule_ident = 3
    output_length = 3
"#;

/// An interface that keeps the last frame sent and where it lay.
#[derive(Default)]
struct Recorder {
    at: usize,
    frame: Vec<u8>,
}

impl Nic for Recorder {
    fn mac(&self) -> MacAddress {
        CONTROLLER
    }
    fn send(&mut self, frame: &[u8]) -> Result<(), SendError> {
        self.at = frame.as_ptr() as usize;
        self.frame = frame.to_vec();
        Ok(())
    }
    fn receive(&mut self, _: &mut dyn FnMut(&[u8])) -> Result<bool, RecvError> {
        Ok(false)
    }
}

/// Sends one cycle's outputs of `OUTPUTS` over exchange `ar` (`None`: as planned) and
/// returns what went out, what the frame written whole from the image is, where the image's
/// frame lies, and the outputs after the send.
fn send_once(ar: Option<CyclicAr>) -> (Recorder, Vec<u8>, usize, Vec<Vec<u8>>) {
    let rig = Rig::of(OUTPUTS);
    let mut image = rig.image;
    let ar = ar.unwrap_or(rig.ar);
    let mut io = PnioIo::new(
        Recorder::default(),
        rig.channel.clone(),
        vec![ar.submodules.clone()],
        1_000_000,
    );
    let start = super::channel::ToCycle::Start(Box::new(ar.clone()));
    assert!(rig.channel.to_cycle.push(start).is_ok());
    let good = SubmoduleStatus {
        input_iops: IOXS_GOOD,
        input_iocs: IOXS_GOOD,
        output_iops: IOXS_GOOD,
        output_iocs: IOXS_GOOD,
    };
    for s in 0..3 {
        image.set_status(s, good);
    }
    assert!(image.set_outputs(0, &[1, 2, 3, 4, 5, 6]));
    assert!(image.set_outputs(2, &[7, 8, 9]));
    io.receive(at(0), Mode::Operate, &mut image);
    io.send(at(0), Mode::Operate, &mut image);

    let mut whole = ar;
    whole.fill(&FromImage(&image));
    let expected = whole.seal(0, data_status::OPERATE).to_vec();
    let frame = image.output_frame(0).expect("the image holds the frame");
    let e = image.submodules()[0];
    let frame_at =
        image.outputs(0).as_ptr() as usize - (e.output_mirror_offset as usize - frame.range.start);
    let outputs = (0..3).map(|s| image.outputs(s).to_vec()).collect();
    (io.nic, expected, frame_at, outputs)
}

#[test]
fn the_output_frame_goes_out_from_the_image_where_the_outputs_are() {
    let (sent, expected, frame_at, outputs) = send_once(None);
    assert_eq!(sent.frame, expected, "the output frame");
    assert_eq!(
        sent.at, frame_at,
        "the frame was not sent from the image's mirror of the outputs"
    );
    assert_eq!(
        outputs[0],
        [1, 2, 3, 4, 5, 6],
        "outputs changed by the send"
    );
    assert_eq!(outputs[2], [7, 8, 9]);
}

#[test]
fn a_frame_laid_out_otherwise_is_written_whole_from_the_image() {
    // The device's AR carries the first output one byte further on than the image does.
    let mut ar = Rig::of(OUTPUTS).ar;
    let first = ar.output.objects.iter_mut().find(|o| o.len == 6).unwrap();
    first.data += 1;
    first.iops += 1;
    let (sent, expected, frame_at, outputs) = send_once(Some(ar));
    assert_eq!(sent.frame, expected, "the output frame");
    assert_ne!(
        sent.at, frame_at,
        "sent from the image's frame, which differs"
    );
    assert_eq!(
        outputs[0],
        [1, 2, 3, 4, 5, 6],
        "outputs changed by the send"
    );
}
