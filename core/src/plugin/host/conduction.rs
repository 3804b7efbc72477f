//! The host's conduction adapter.

use super::*;

/// A conduction plugin model behind [`ConductionModel`].
///
/// The trait's temperature reads cannot fail; when the plugin's do, the adapter fills the output
/// with NaN (which every consumer's temperature check rejects) and returns the plugin's message
/// from the next `step` or `uniform_state`.
pub struct ConductionAdapter {
    handle: Handle,
    functions: &'static ConductionFunctions,
    /// n_states, n_nodes, n_surface_panels.
    sizes: [usize; 3],
    pending: RefCell<Option<ModelError>>,
}

impl ConductionAdapter {
    pub(crate) fn create(
        entry: &'static PluginModel,
        functions: &'static ConductionFunctions,
        name: &str,
        context: &ModelContext<'_>,
    ) -> Result<Self, ModelError> {
        let handle = Handle::create(entry, name, context)?;
        let mut sizes = [0usize; 3];
        // SAFETY: room for the 3 sizes.
        let status = unsafe { (functions.sizes)(handle.raw, sizes.as_mut_ptr()) };
        handle.check(status, "sizes")?;
        Ok(Self {
            handle,
            functions,
            sizes,
            pending: RefCell::new(None),
        })
    }

    fn take_pending(&self) -> Result<(), ModelError> {
        match self.pending.borrow_mut().take() {
            Some(error) => Err(error),
            None => Ok(()),
        }
    }

    fn read(
        &self,
        function: ReadStateFn,
        what: &str,
        state: &DVector<f64>,
        out_k: &mut [f64],
        expected: usize,
    ) {
        let name = &self.handle.name;
        let result = check_len(name, "state values", state.len(), self.sizes[0])
            .and_then(|()| check_len(name, &format!("{what} slots"), out_k.len(), expected))
            .and_then(|()| {
                // SAFETY: state and output have the lengths the plugin reported.
                let status = unsafe {
                    function(
                        self.handle.raw,
                        state.as_ptr(),
                        state.len(),
                        out_k.as_mut_ptr(),
                        out_k.len(),
                    )
                };
                self.handle.check(status, what)
            })
            .and_then(|()| check_finite(name, what, out_k, 1, "entry"));
        if let Err(error) = result {
            out_k.fill(f64::NAN);
            self.pending.borrow_mut().get_or_insert(error);
        }
    }
}

impl ConductionModel for ConductionAdapter {
    fn name(&self) -> &str {
        &self.handle.name
    }

    fn n_states(&self) -> usize {
        self.sizes[0]
    }

    fn n_nodes(&self) -> usize {
        self.sizes[1]
    }

    fn n_surface_panels(&self) -> usize {
        self.sizes[2]
    }

    fn uniform_state(&self, temperature_k: f64) -> Result<DVector<f64>, ModelError> {
        self.take_pending()?;
        let mut state = DVector::zeros(self.sizes[0]);
        // SAFETY: the state has the length the plugin reported.
        let status = unsafe {
            (self.functions.uniform_state)(
                self.handle.raw,
                temperature_k,
                state.as_mut_ptr(),
                state.len(),
            )
        };
        self.handle.check(status, "uniform state")?;
        check_finite(
            &self.handle.name,
            "uniform state",
            state.as_slice(),
            1,
            "state",
        )?;
        Ok(state)
    }

    fn step(
        &mut self,
        state: &mut DVector<f64>,
        surface_heat_flux_w_m2: &[f64],
        dt_s: f64,
    ) -> Result<(), ModelError> {
        self.take_pending()?;
        let name = &self.handle.name;
        check_len(name, "state values", state.len(), self.sizes[0])?;
        check_len(
            name,
            "surface heat fluxes",
            surface_heat_flux_w_m2.len(),
            self.sizes[2],
        )?;
        check_step_inputs(name, surface_heat_flux_w_m2, dt_s)?;
        // SAFETY: state and heat flux have the lengths the plugin reported.
        let status = unsafe {
            (self.functions.step)(
                self.handle.raw,
                state.as_mut_ptr(),
                state.len(),
                surface_heat_flux_w_m2.as_ptr(),
                surface_heat_flux_w_m2.len(),
                dt_s,
            )
        };
        self.handle.check(status, "step")?;
        check_finite(name, "thermal state", state.as_slice(), 1, "state")
    }

    fn surface_temperatures(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        let function = self.functions.surface_temperatures;
        self.read(
            function,
            "surface temperatures",
            state,
            out_k,
            self.sizes[2],
        );
    }

    fn node_temperatures(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        let function = self.functions.node_temperatures;
        self.read(function, "node temperatures", state, out_k, self.sizes[1]);
    }

    fn node_temperature_differences(&self, state: &DVector<f64>, out_k: &mut [f64]) {
        let function = self.functions.node_temperature_differences;
        self.read(
            function,
            "node temperature differences",
            state,
            out_k,
            self.sizes[1],
        );
    }
}
