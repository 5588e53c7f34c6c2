//! The `Model` class (the Lafortune model with a parameter layout: evaluate, residuals, RMSE,
//! Jacobian) and `rmse`, the RMSE of given parameters as `brdf-sls eval` prints it.

use std::borrow::Cow;
use std::collections::BTreeMap;

use brdf_model::{DataSet, Evaluator, Kernel, Layout};
use numpy::ndarray::{Array2, ArrayView1, ShapeBuilder};
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLike1, PyArrayLike2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::data::{PyDataSet, dataset_from_arrays};
use crate::support::{input_err, parse_params, to_python};

/// The parameters of a paper name ("tuning", "cross", ...) as a dict.
#[pyfunction]
pub fn named_params(py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
    let p = brdf_model::named_params(name).ok_or_else(|| {
        input_err(format!(
            "`{name}`: not a known name ({})",
            brdf_model::NAMED_PARAMS.join(", ")
        ))
    })?;
    to_python(py, &p)
}

/// The model families known by name, in the order `brdf-sls` lists them: one dict each with
/// `name`, `summary`, `kinds` (the lobe kinds it has), `shared` and `lobe` (its field names).
#[pyfunction]
pub fn families(py: Python<'_>) -> PyResult<Py<PyAny>> {
    let list: Vec<BTreeMap<&str, serde_json::Value>> = brdf_model::family_names()
        .into_iter()
        .filter_map(|n| brdf_model::family(n).ok())
        .map(|f| {
            let names =
                |fs: &[brdf_model::FieldDef]| -> Vec<&str> { fs.iter().map(|d| d.name).collect() };
            BTreeMap::from([
                ("name", serde_json::json!(f.name())),
                ("summary", serde_json::json!(f.summary())),
                (
                    "kinds",
                    serde_json::json!(f.kinds().iter().map(|k| k.name()).collect::<Vec<_>>()),
                ),
                ("shared", serde_json::json!(names(f.shared_fields()))),
                ("lobe", serde_json::json!(names(f.lobe_fields()))),
            ])
        })
        .collect();
    to_python(py, &list)
}

/// The RMSE of `params` (of any family) on `data`, exactly as `brdf-sls eval` computes it (a
/// layout of as many lobes as `params` has, each of the family's fullest kind; the fastest
/// kernel).
#[pyfunction]
pub fn rmse(py: Python<'_>, params: &Bound<'_, PyAny>, data: &PyDataSet) -> PyResult<f64> {
    let params = parse_params(params)?;
    if data.data.is_empty() {
        return Err(input_err("data: no samples"));
    }
    let layout = Layout::of_params(&params).map_err(input_err)?;
    let x = layout.encode(&params);
    let d = data.data.clone();
    Ok(py.detach(move || Evaluator::new(&layout).rmse(&x, &layout.prepare(&d))))
}

/// A model family with a parameter layout, as `brdf-sls fit` builds it from `--family`,
/// `--lobes`, `--kind`, `--exponent` and `--fix`.
///
/// Methods take either physical parameters (a name, dict or JSON: see `encode`) or `x`, the
/// free parameters in the optimiser's coordinates (a 1-D array of length `dim`, read without
/// copying when it is a contiguous float64 array).
#[pyclass(frozen, name = "Model", module = "brdf_sls._native")]
pub struct PyModel {
    layout: Layout,
    kernel: Kernel,
}

impl PyModel {
    /// `x` from Python: an array of the free parameters or physical parameters to encode.
    fn point<'a>(&self, p: &'a Bound<'_, PyAny>) -> PyResult<Point<'a>> {
        if p.is_instance_of::<PyString>() || p.is_instance_of::<PyDict>() {
            return Ok(Point::Owned(self.layout.encode(&parse_params(p)?)));
        }
        let arr: PyArrayLike1<'_, f64, AllowTypeChange> = p.extract().map_err(|_| {
            input_err(format!(
                "x: expected parameters (a name, dict or JSON) or an array of the {} free parameters {:?}",
                self.layout.dim(),
                self.layout.free_names()
            ))
        })?;
        let n = arr.as_array().len();
        if n != self.layout.dim() {
            return Err(input_err(format!(
                "x: {n} values; the model has {} free parameters {:?}",
                self.layout.dim(),
                self.layout.free_names()
            )));
        }
        Ok(Point::Array(arr))
    }

    fn evaluator(&self) -> PyResult<Evaluator> {
        Evaluator::with_kernel(&self.layout, self.kernel).map_err(input_err)
    }
}

/// A point in the optimiser's coordinates: borrowed from numpy or encoded here.
enum Point<'a> {
    Array(PyArrayLike1<'a, f64, AllowTypeChange>),
    Owned(Vec<f64>),
}

impl Point<'_> {
    fn slice(&self) -> Cow<'_, [f64]> {
        match self {
            Point::Array(a) => match a.as_slice() {
                Ok(s) => Cow::Borrowed(s),
                Err(_) => Cow::Owned(a.as_array().to_vec()),
            },
            Point::Owned(v) => Cow::Borrowed(v),
        }
    }
}

#[pymethods]
impl PyModel {
    /// family: "lafortune" (default), "ggx", "cook-torrance", ... (brdf_sls.families());
    /// lobes: 1 to 64; kind: "anisotropic" or "isotropic" (default: anisotropic where the
    /// family has it); exponent: "log1p" (default: the family's log coordinate of its shape
    /// parameters) or "raw"; fixed: {"lobe1.pan": 45.0, ...} held fixed; kernel: "auto",
    /// "avx512", "avx2", "portable" or "scalar".
    #[new]
    #[pyo3(signature = (lobes=1, kind=None, exponent="log1p", fixed=None, kernel="auto", *, family="lafortune"))]
    fn new(
        lobes: usize,
        kind: Option<&str>,
        exponent: &str,
        fixed: Option<BTreeMap<String, f64>>,
        kernel: &str,
        family: &str,
    ) -> PyResult<Self> {
        let spec = crate::support::model_spec(family, lobes, kind, exponent, fixed)?;
        let layout = spec.layout().map_err(input_err)?;
        let kernel: Kernel = kernel.parse().map_err(input_err)?;
        let kernel = kernel.resolve().map_err(input_err)?;
        Ok(PyModel { layout, kernel })
    }

    /// Number of free parameters (the length of `x`).
    #[getter]
    fn dim(&self) -> usize {
        self.layout.dim()
    }

    /// Names of the free parameters, in the order of `x`.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.layout.free_names().to_vec()
    }

    /// The concrete evaluation kernel.
    #[getter]
    fn kernel(&self) -> String {
        self.kernel.to_string()
    }

    /// Lower bounds of `x` (optimiser coordinates).
    #[getter]
    fn lower<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.layout.lower())
    }

    /// Upper bounds of `x` (optimiser coordinates).
    #[getter]
    fn upper<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.layout.upper())
    }

    /// Physical parameters (name, dict or JSON) as `x` (fixed ones dropped).
    fn encode<'py>(
        &self,
        py: Python<'py>,
        params: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = self.layout.encode(&parse_params(params)?);
        Ok(PyArray1::from_vec(py, x))
    }

    /// `x` as physical parameters (a dict, fixed ones included).
    fn decode(&self, py: Python<'_>, x: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let x = self.point(x)?;
        to_python(py, &self.layout.decode(&x.slice()))
    }

    /// The model's values at directions `u`, `v` (arrays of shape (n, 3)).
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: PyArrayLike2<'py, f64, AllowTypeChange>,
        v: PyArrayLike2<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        // Residuals against zero values are the model's values.
        let zeros = vec![0.0; u.as_array().nrows()];
        let data = dataset_from_arrays(&u, &v, ArrayView1::from(&zeros[..]))?;
        self.residuals_of(py, x, &data)
    }

    /// Residuals `f(u_i, v_i) - value_i` of `x` on `data`.
    fn residuals<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        data: &PyDataSet,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.residuals_of(py, x, &data.data)
    }

    /// Root-mean-square error of `x` on `data`.
    fn rmse(&self, py: Python<'_>, x: &Bound<'_, PyAny>, data: &PyDataSet) -> PyResult<f64> {
        let x = self.point(x)?;
        let x = x.slice();
        let mut ev = self.evaluator()?;
        let d = &data.data;
        let layout = &self.layout;
        Ok(py.detach(|| ev.rmse(&x, &layout.prepare(d))))
    }

    /// The Jacobian of the residuals, shape (n, dim): column j is d r / d x_j in the
    /// optimiser's coordinates (pan columns per degree). Handed to numpy without a copy
    /// (Fortran order, as the evaluator computes it).
    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        data: &PyDataSet,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let x = self.point(x)?;
        let x = x.slice();
        let (m, p) = (data.data.len(), self.layout.dim());
        let mut ev = self.evaluator()?;
        let d = &data.data;
        let layout = &self.layout;
        let jac = py.detach(|| {
            let mut jac = vec![0.0; m * p];
            ev.jacobian(&x, &layout.prepare(d), &mut jac);
            jac
        });
        let a = Array2::from_shape_vec((m, p).f(), jac).map_err(input_err)?;
        Ok(PyArray2::from_owned_array(py, a))
    }

    /// The model family's name.
    #[getter]
    fn family(&self) -> &'static str {
        self.layout.family().name()
    }

    fn __repr__(&self) -> String {
        format!(
            "Model({}, {} lobe(s), free parameters {:?}, kernel {})",
            self.layout.family().name(),
            self.layout.lobe_count(),
            self.layout.free_names(),
            self.kernel
        )
    }
}

impl PyModel {
    fn residuals_of<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        data: &DataSet,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = self.point(x)?;
        let x = x.slice();
        let mut ev = self.evaluator()?;
        let layout = &self.layout;
        let r = py.detach(|| {
            let mut r = vec![0.0; data.len()];
            // Overflow near n = 10000 gives +inf values, which the caller sees as such.
            ev.residuals(&x, &layout.prepare(data), &mut r);
            r
        });
        Ok(PyArray1::from_vec(py, r))
    }
}
