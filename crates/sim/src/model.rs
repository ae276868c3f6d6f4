//! Plant models. A model is a small continuous-time process advanced in steps of
//! virtual time; it knows nothing of devices (binding and scaling to X/Y/D are the
//! scenario runner's job).

/// A plant model.
pub trait Model: Send {
    /// Names of the inputs it reads (actuators driven by the PLC), in order.
    fn inputs(&self) -> &[&'static str];
    /// Names of the outputs it produces (sensors read by the PLC), in order.
    fn outputs(&self) -> &[&'static str];
    /// Advances the model by `dt` seconds with `inputs` held constant over the
    /// step, then writes the outputs at the end of the step.
    fn step(&mut self, dt: f64, inputs: &[f64], outputs: &mut [f64]);
    /// The outputs in the current state, without advancing.
    fn outputs_now(&self, outputs: &mut [f64]);
}
