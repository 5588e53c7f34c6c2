//! The `DataSet` class: samples read from Cornell, CSV or MERL files under the command line's
//! data policy, built from numpy arrays, or generated as `brdf-sls gen` does.

use std::path::PathBuf;
use std::sync::Arc;

use brdf_experiment::spec::{FileSpec, FormatName};
use brdf_io::Channel;
use brdf_model::{DataSet, MAX_SAMPLES};
use numpy::ndarray::{Array2, ArrayView1};
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLike1, PyArrayLike2};
use pyo3::prelude::*;

use crate::support::{enum_value, input_err, parse_params};

/// BRDF samples: incident directions `u`, exitant directions `v` (unit vectors in the surface
/// frame, both pointing away from the surface, z the normal) and measured values.
///
/// Build one with `DataSet.read(path, ...)`, `DataSet.from_arrays(u, v, values)` or
/// `DataSet.synthetic(params, samples, sigma, seed)`. The data are immutable: `values` and
/// `column(name)` are read-only numpy views of the stored columns (no copy).
#[pyclass(frozen, name = "DataSet", module = "brdf_sls._native")]
pub struct PyDataSet {
    /// The samples, shared with fits and models without copying.
    pub data: Arc<DataSet>,
    /// What the reader's filters dropped (files only).
    report: Option<String>,
}

impl PyDataSet {
    fn new(data: DataSet, report: Option<String>) -> Self {
        PyDataSet {
            data: Arc::new(data),
            report,
        }
    }
}

/// The stored columns by name.
const COLUMNS: [&str; 7] = ["ux", "uy", "uz", "vx", "vy", "vz", "value"];

fn column<'a>(d: &'a DataSet, name: &str) -> PyResult<&'a [f64]> {
    Ok(match name {
        "ux" => d.u_x(),
        "uy" => d.u_y(),
        "uz" => d.u_z(),
        "vx" => d.v_x(),
        "vy" => d.v_y(),
        "vz" => d.v_z(),
        "value" | "values" => d.values(),
        _ => {
            return Err(input_err(format!(
                "column `{name}`: expected one of {}",
                COLUMNS.join(", ")
            )));
        }
    })
}

/// An (n, 3) array of directions as three columns, checked: finite values.
fn direction_columns(
    name: &str,
    a: &PyArrayLike2<'_, f64, AllowTypeChange>,
) -> PyResult<[Vec<f64>; 3]> {
    let view = a.as_array();
    if view.ncols() != 3 {
        return Err(input_err(format!(
            "{name}: expected an array of shape (n, 3), found {:?}",
            view.shape()
        )));
    }
    if let Some(i) = view
        .rows()
        .into_iter()
        .position(|r| r.iter().any(|x| !x.is_finite()))
    {
        return Err(input_err(format!("{name}[{i}]: expected finite numbers")));
    }
    Ok([0, 1, 2].map(|j| view.column(j).to_vec()))
}

/// A data set from (n, 3) direction arrays and values, checked (shapes, finite numbers, the
/// sample limit) and copied once into the structure-of-arrays layout.
pub fn dataset_from_arrays(
    u: &PyArrayLike2<'_, f64, AllowTypeChange>,
    v: &PyArrayLike2<'_, f64, AllowTypeChange>,
    values: ArrayView1<'_, f64>,
) -> PyResult<DataSet> {
    let n = values.len();
    if n > MAX_SAMPLES {
        return Err(input_err(format!(
            "values: {n} samples, at most {MAX_SAMPLES}"
        )));
    }
    let [ux, uy, uz] = direction_columns("u", u)?;
    let [vx, vy, vz] = direction_columns("v", v)?;
    if ux.len() != n || vx.len() != n {
        return Err(input_err(format!(
            "u, v, values: expected the same number of rows, found {}, {} and {n}",
            ux.len(),
            vx.len()
        )));
    }
    if let Some(i) = values.iter().position(|x| !x.is_finite()) {
        return Err(input_err(format!("values[{i}]: expected a finite number")));
    }
    DataSet::from_columns([ux, uy, uz, vx, vy, vz, values.to_vec()])
        .ok_or_else(|| input_err("u, v, values: lengths differ"))
}

#[pymethods]
impl PyDataSet {
    /// Reads a data file as `brdf-sls fit/eval/info` do (same filters, same errors).
    ///
    /// format: "cornell", "csv", "merl" or "alta" (default: from the extension; an unknown
    /// extension is an error); wavelength: Cornell nm (default 550; Cornell files only);
    /// channel: "red", "green" (default) or "blue" (MERL and ALTA RGB files only); param_out:
    /// what an ALTA file's values are when its header lacks #PARAM_OUT ("INV_STERADIAN",
    /// "INV_STERADIAN_COSINE_FACTOR", "RGB_COLOR"); max_value: drop values above it (the paper
    /// used 1); drop_negative: drop negative values; keep_below_horizon: keep samples below
    /// the horizon. Raises InputError naming the file and line on bad data.
    #[staticmethod]
    #[pyo3(signature = (path, *, format=None, wavelength=None, channel=None, param_out=None, max_value=None, drop_negative=false, keep_below_horizon=false))]
    #[allow(clippy::too_many_arguments)]
    fn read(
        py: Python<'_>,
        path: PathBuf,
        format: Option<&str>,
        wavelength: Option<f64>,
        channel: Option<&str>,
        param_out: Option<&str>,
        max_value: Option<f64>,
        drop_negative: bool,
        keep_below_horizon: bool,
    ) -> PyResult<Self> {
        let fs = FileSpec {
            path,
            format: format
                .map(|f| {
                    f.parse::<FormatName>()
                        .map_err(|e| input_err(format!("format: {e}")))
                })
                .transpose()?,
            wavelength,
            channel: channel
                .map(|c| enum_value::<Channel>("channel", c))
                .transpose()?,
            param_out: param_out
                .map(|o| enum_value::<brdf_io::AltaOutput>("param_out", o))
                .transpose()?,
            max_value,
            drop_negative,
            drop_below_horizon: !keep_below_horizon,
        };
        let (data, report) = py
            .detach(|| brdf_fit::load_data(&fs))
            .map_err(input_err)?;
        Ok(PyDataSet::new(data, Some(report.to_string())))
    }

    /// A data set from numpy arrays: `u` and `v` of shape (n, 3), `values` of shape (n,).
    /// Taken as given (no filters); the arrays are copied once into the model's
    /// structure-of-arrays layout. Non-finite numbers raise InputError naming the row.
    #[staticmethod]
    fn from_arrays(
        u: PyArrayLike2<'_, f64, AllowTypeChange>,
        v: PyArrayLike2<'_, f64, AllowTypeChange>,
        values: PyArrayLike1<'_, f64, AllowTypeChange>,
    ) -> PyResult<Self> {
        let data = dataset_from_arrays(&u, &v, values.as_array())?;
        Ok(PyDataSet::new(data, None))
    }

    /// A synthetic instance as `brdf-sls gen` writes it: `samples` directions uniform over
    /// the hemisphere, values of `params` (a name such as "tuning", a dict or JSON) plus
    /// Gaussian noise `sigma`, seeded by `seed` (the same seed gives the same data).
    #[staticmethod]
    #[pyo3(signature = (params, samples=10000, sigma=0.0, seed=1))]
    fn synthetic(
        py: Python<'_>,
        params: &Bound<'_, PyAny>,
        samples: usize,
        sigma: f64,
        seed: u64,
    ) -> PyResult<Self> {
        let params = parse_params(params)?;
        let data = py
            .detach(|| brdf_model::try_synthetic(&params, samples, sigma, seed))
            .map_err(input_err)?;
        Ok(PyDataSet::new(data, None))
    }

    /// Number of samples.
    fn __len__(&self) -> usize {
        self.data.len()
    }

    fn __repr__(&self) -> String {
        match &self.report {
            Some(r) => format!("DataSet({} samples; {r})", self.data.len()),
            None => format!("DataSet({} samples)", self.data.len()),
        }
    }

    /// What the reader's filters dropped (None for arrays and synthetic data).
    #[getter]
    fn filter_report(&self) -> Option<String> {
        self.report.clone()
    }

    /// The measured values: a read-only view of the stored column (no copy).
    #[getter]
    fn values<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Self::column(slf, "value")
    }

    /// One stored column ("ux", "uy", "uz", "vx", "vy", "vz", "value") as a read-only view
    /// (no copy).
    fn column<'py>(slf: &Bound<'py, Self>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let data = &slf.get().data;
        let view = ArrayView1::from(column(data, name)?);
        // SAFETY: the array borrows the column of a DataSet that is never mutated (frozen
        // class, data behind an Arc) and `slf`, its owner, is kept alive as the array's base.
        let array = unsafe { PyArray1::borrow_from_array(&view, slf.clone().into_any()) };
        array.getattr("flags")?.setattr("writeable", false)?;
        Ok(array)
    }

    /// Incident directions as an (n, 3) array (a copy: the columns are stored apart).
    #[getter]
    fn u<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let d = &self.data;
        directions(py, [d.u_x(), d.u_y(), d.u_z()])
    }

    /// Exitant directions as an (n, 3) array (a copy: the columns are stored apart).
    #[getter]
    fn v<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let d = &self.data;
        directions(py, [d.v_x(), d.v_y(), d.v_z()])
    }

    /// Writes the data set as CSV (`ux,uy,uz,vx,vy,vz,value`, round-trip exact), as
    /// `brdf-sls gen --out` does.
    fn write_csv(&self, path: PathBuf) -> PyResult<()> {
        let mut buf = Vec::new();
        self.data.write_csv(&mut buf).map_err(input_err)?;
        brdf_experiment::store::write_atomic(&path, &buf)
            .map_err(|e| crate::support::run_err(format!("writing {}: {e}", path.display())))
    }
}

/// Three columns as an (n, 3) array, handed to numpy without a further copy.
fn directions<'py>(py: Python<'py>, cols: [&[f64]; 3]) -> Bound<'py, PyArray2<f64>> {
    let n = cols[0].len();
    let a = Array2::from_shape_fn((n, 3), |(i, j)| cols[j][i]);
    PyArray2::from_owned_array(py, a)
}
