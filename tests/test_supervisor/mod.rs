//! A test supervisor for the GUI's tests without a controller: the supervisor's end of
//! the real request channel, and a `ViewSource` giving a `View` made by hand. It sees
//! every request the GUI sends and answers as the test says.
#![allow(dead_code)]

use std::cell::Cell;

use mechweed::gui::view::{View, ViewSource};
use mechweed::state::modes::{Mode, Refusal, Request};
use mechweed::state::request_channel::{Answer, Envelope, RequestReceiver, SupervisorHandle};
use mechweed::state::shared;
use mechweed::state::status::{PowerState, Status};

/// The supervisor's end of a real request channel, played by the test.
pub struct TestSupervisor {
    pub handle: SupervisorHandle,
    /// None: the supervisor has stopped.
    pub inbox: Option<RequestReceiver>,
    /// What `view()` gives.
    pub view: View,
    /// Camera-link round trips asked for.
    pub pings: Cell<usize>,
}

impl TestSupervisor {
    pub fn new(view: View) -> TestSupervisor {
        let (_status, reader) = shared(Status::default());
        let (handle, inbox) = mechweed::state::request_channel::channel(reader);
        TestSupervisor {
            handle,
            inbox: Some(inbox),
            view,
            pings: Cell::new(0),
        }
    }

    /// The requests waiting, each answered with `answer`.
    pub fn answer(&self, answer: impl Fn(&Request) -> Result<(), Refusal>) -> Vec<Request> {
        let inbox = self.inbox.as_ref().expect("the test supervisor runs");
        let mut taken = Vec::new();
        while let Ok(Envelope { request, reply, .. }) = inbox.try_recv() {
            reply.try_send((request, answer(&request))).unwrap();
            taken.push(request);
        }
        taken
    }

    /// Requests sent and not yet taken.
    pub fn waiting(&self) -> usize {
        self.inbox.as_ref().map_or(0, |inbox| inbox.len())
    }
}

impl ViewSource for TestSupervisor {
    fn view(&mut self) -> View {
        self.view.clone()
    }

    fn send(
        &self,
        request: Request,
        reply: &crossbeam_channel::Sender<Answer>,
    ) -> Result<(), String> {
        self.handle.send(request, reply)
    }

    fn ping_link(&self) {
        self.pings.set(self.pings.get() + 1);
    }
}

/// A robot whose supervisor has run: in `mode`, motor power `power`, calibrated.
pub fn robot(mode: Mode, power: PowerState) -> View {
    let mut view = View {
        now_s: 12.0,
        ..View::default()
    };
    view.status.tick = 1200;
    view.status.t_s = 12.0;
    view.status.mode = mode;
    view.status.power = power;
    view.status.measured.calibrated = true;
    view.status.inputs.estop_front_released = true;
    view.status.inputs.estop_back_released = true;
    view
}
