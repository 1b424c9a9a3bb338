! granmpm.f90 - Fortran 2003 interface to libgranmpm (module granmpm).
!
! The C API of granmpm.h, one to one, through iso_c_binding: bind(c)
! derived types with the layout of the C structures, named constants for
! the enumerations, and interfaces to every exported function. The module
! holds no code of its own (only the .mod file is needed); link with the C
! library: `gfortran prog.f90 $(pkg-config --cflags --libs granmpm)`.
! See granmpm(3), section HOSTS IN OTHER LANGUAGES, and examples/freefall.f90.
!
! Conventions, as in C:
!  - start every structure from its defaults, written by the library:
!      status = gm_domain_def_init(def, c_sizeof(def))
!    (the gm_*_init functions; the C header's inline gm_*_default() are not
!    callable from Fortran). status == GM_OK, and def%struct_size ==
!    c_sizeof(def) after the call, show that this module and the library
!    agree on the structure's size;
!  - every function returning integer(c_int) status returns GM_OK (0) or a
!    negative GM_ERR_*; gm_domain_last_error(domain) and gm_strerror(status)
!    return C strings (type(c_ptr)), read them with c_f_pointer;
!  - arrays indexed by a C enumeration are declared from 0 so that the
!    constants index them directly: def%walls(GM_FACE_YMIN),
!    batch%stress(GM_XY); vectors (origin, gravity, velocity ...) are 1..3
!    for x, y, z; per-point arrays are interleaved as in C,
!    position(k + dim*(i-1)) for point i, component k;
!  - strings passed to the library end with c_null_char:
!      status = gm_domain_write_vtu(domain, "out.vtu" // c_null_char)
!  - pointers in structures (names, point arrays) are type(c_ptr): set them
!    with c_loc of a target array that outlives the call;
!  - callbacks (material updates, hooks, task systems) are type(c_funptr)
!    from c_funloc of a bind(c) procedure with the C signature.
!
! SPDX-License-Identifier: BSD-2-Clause
module granmpm
  use, intrinsic :: iso_c_binding
  implicit none

  ! gm_status
  integer(c_int), parameter :: GM_OK = 0, GM_ERR_NULL = -1, &
    GM_ERR_INVALID_ARGUMENT = -2, GM_ERR_STRUCT_SIZE = -3, &
    GM_ERR_NO_MEMORY = -4, GM_ERR_OUT_OF_GRID = -5, GM_ERR_NOT_FINITE = -6, &
    GM_ERR_UNSTABLE_DT = -7, GM_ERR_CALLBACK = -8, &
    GM_ERR_UNKNOWN_MATERIAL = -9, GM_ERR_UNKNOWN_POINT = -10, &
    GM_ERR_IO = -11, GM_ERR_BUSY = -12, GM_ERR_UNSUPPORTED = -13
  ! gm_geometry
  integer(c_int), parameter :: GM_GEOMETRY_1D = 1, &
    GM_GEOMETRY_PLANE_STRAIN = 2, GM_GEOMETRY_AXISYMMETRIC = 3, &
    GM_GEOMETRY_3D = 4
  ! gm_update_scheme
  integer(c_int), parameter :: GM_SCHEME_USL = 0, GM_SCHEME_MUSL = 1, &
    GM_SCHEME_USF = 2
  ! gm_shape
  integer(c_int), parameter :: GM_SHAPE_LINEAR = 0, GM_SHAPE_UGIMP = 1, &
    GM_SHAPE_CPGIMP = 2, GM_SHAPE_CPDI = 3, GM_SHAPE_BSPLINE2 = 4, &
    GM_SHAPE_BSPLINE3 = 5
  ! gm_family
  integer(c_int), parameter :: GM_FAMILY_PLAIN = 0, &
    GM_FAMILY_STRESS_FREE = 1, GM_FAMILY_GRANULAR = 2
  ! gm_wall_type
  integer(c_int), parameter :: GM_WALL_OPEN = 0, GM_WALL_FIXED = 1, &
    GM_WALL_SLIP = 2, &
    GM_WALL_PERIODIC = 3
  ! faces of the grid box: indices into gm_domain_def%walls(0:5)
  integer(c_int), parameter :: GM_FACE_XMIN = 0, GM_FACE_XMAX = 1, &
    GM_FACE_YMIN = 2, GM_FACE_YMAX = 3, GM_FACE_ZMIN = 4, GM_FACE_ZMAX = 5
  ! Voigt components: indices into gm_material_batch%stress(0:5) and
  ! %strain_increment(0:5); component GM_XX + 1 .. of GM_FIELD_STRESS
  integer(c_int), parameter :: GM_XX = 0, GM_YY = 1, GM_ZZ = 2, GM_XY = 3, &
    GM_YZ = 4, GM_ZX = 5
  ! gm_density_control
  integer(c_int), parameter :: GM_DENSITY_CONTROL_RETURN = 0, &
    GM_DENSITY_CONTROL_SCALE = 1
  ! gm_point_state
  integer(c_int), parameter :: GM_STATE_QUASI_STATIC = 0, &
    GM_STATE_MODERATE = 1, GM_STATE_DISCONNECTED = 2
  ! gm_field
  integer(c_int), parameter :: GM_FIELD_POSITION = 0, &
    GM_FIELD_VELOCITY = 1, GM_FIELD_EXTERNAL_FORCE = 2, GM_FIELD_MASS = 3, &
    GM_FIELD_VOLUME = 4, GM_FIELD_INITIAL_VOLUME = 5, GM_FIELD_DENSITY = 6, &
    GM_FIELD_STRESS = 7, GM_FIELD_DEFORMATION_GRADIENT = 8, &
    GM_FIELD_MATERIAL = 9, GM_FIELD_ID = 10, GM_FIELD_DOMAIN_SIZE = 11, &
    GM_FIELD_DOMAIN_CORNERS = 12, GM_FIELD_STATE = 13, &
    GM_FIELD_COMPONENT = 14, GM_FIELD_AFFINE = 15
  ! gm_transfer
  integer(c_int), parameter :: GM_TRANSFER_FLIP = 0, GM_TRANSFER_APIC = 1
  ! gm_volumetric (gm_domain_set_volumetric, provisional)
  integer(c_int), parameter :: GM_VOLUMETRIC_POINT = 0, &
      GM_VOLUMETRIC_CELL_MEAN = 1
  ! gm_hook_stage
  integer(c_int), parameter :: GM_HOOK_BEFORE_STEP = 0, &
    GM_HOOK_AFTER_STEP = 1
  ! state variables of the built-in materials (indices into batch%state)
  integer(c_int), parameter :: GM_MOHR_COULOMB_PLASTIC_SHEAR_STRAIN = 0, &
    GM_MOHR_COULOMB_STATE_COUNT = 1, GM_DRUCKER_PRAGER_STATE_COUNT = 1, &
    GM_PERZYNA_STATE_COUNT = 1, GM_FILLING_STATE_COUNT = 2, &
    GM_VON_MISES_PLASTIC_STRAIN = 0, GM_VON_MISES_STATE_COUNT = 1, &
    GM_MU_I_PLASTIC_STRAIN = 0, GM_MU_I_INERTIAL_NUMBER = 1, &
    GM_MU_I_STATE_COUNT = 2
  ! version of the C header this module matches (GM_VERSION_NUMBER in C;
  ! renamed: Fortran names are case-insensitive and gm_version_number is
  ! the function)
  integer(c_int), parameter :: GM_VERSION_MAJOR = 0, GM_VERSION_MINOR = 1, &
    GM_VERSION_PATCH = 0, GM_MODULE_VERSION_NUMBER = 100

  ! Structures: the C structures field by field (granmpm.h for units and
  ! meaning). Enumerations are integer(c_int), size_t integer(c_size_t),
  ! uint64_t integer(c_int64_t), pointers type(c_ptr), function pointers
  ! type(c_funptr).

  type, bind(c) :: gm_domain_def
    integer(c_size_t) :: struct_size
    integer(c_int) :: geometry
    real(c_double) :: origin(3), extent(3)   ! m
    real(c_double) :: cell_size              ! m
    real(c_double) :: gravity(3)             ! m/s^2
    integer(c_int) :: scheme
    integer(c_int) :: walls(0:5)             ! by GM_FACE_*
    real(c_double) :: cfl
    integer(c_int) :: refuse_unstable_dt, max_retries, worker_count
    type(c_funptr) :: enqueue_task, finish_task
    type(c_ptr) :: task_user
    real(c_double) :: damping
    integer(c_int) :: shape, family
    real(c_double) :: pic_fraction
    integer(c_int) :: transfer               ! gm_transfer
  end type gm_domain_def

  type, bind(c) :: gm_material_batch
    integer(c_size_t) :: struct_size, count
    integer(c_int) :: worker, material, geometry
    real(c_double) :: dt                           ! s
    type(c_ptr) :: strain_increment(0:5)           ! const double *, by GM_XX..
    type(c_ptr) :: density                         ! const double *, kg/m^3
    type(c_ptr) :: stress(0:5)                     ! double *, Pa
    type(c_ptr) :: state                           ! double *const *
    integer(c_size_t) :: state_count
    type(c_ptr) :: point_id                        ! const int64_t *
  end type gm_material_batch

  type, bind(c) :: gm_material_def
    integer(c_size_t) :: struct_size
    type(c_ptr) :: name
    type(c_funptr) :: update
    type(c_ptr) :: user
    integer(c_size_t) :: state_count
    type(c_ptr) :: initial_state
    real(c_double) :: p_wave_modulus   ! Pa
    real(c_double) :: density          ! kg/m^3
  end type gm_material_def

  type, bind(c) :: gm_elastic_def
    integer(c_size_t) :: struct_size
    type(c_ptr) :: name
    real(c_double) :: youngs_modulus, poisson_ratio, density
  end type gm_elastic_def

  type, bind(c) :: gm_wall_def
    integer(c_size_t) :: struct_size
    real(c_double) :: point(3), normal(3)
    real(c_double) :: friction_static, friction_kinetic
  end type gm_wall_def

  type, bind(c) :: gm_wall_force
    integer(c_size_t) :: struct_size
    real(c_double) :: force(3), normal, tangential   ! N
    real(c_double) :: impulse(3), normal_impulse, tangential_impulse ! N s
    real(c_double) :: duration                       ! s
    real(c_double) :: total_impulse(3)               ! N s
    real(c_double) :: total_duration                 ! s
    real(c_double) :: smoothed_force(3), smoothed_normal, smoothed_tangential ! N
    real(c_double) :: smoothing_time                 ! s
  end type gm_wall_force

  type, bind(c) :: gm_rigid_load
    integer(c_size_t) :: struct_size
    real(c_double) :: force(3)                       ! N
    real(c_double) :: impulse(3)                     ! N s
    real(c_double) :: duration                       ! s
    real(c_double) :: total_impulse(3)               ! N s
    real(c_double) :: total_duration                 ! s
    real(c_double) :: smoothed_force(3)              ! N
    real(c_double) :: smoothing_time                 ! s
  end type gm_rigid_load

  type, bind(c) :: gm_wall_traction
    real(c_double) :: position, normal, tangential
  end type gm_wall_traction

  type, bind(c) :: gm_rigid_def
    integer(c_size_t) :: struct_size
    type(c_ptr) :: name
    real(c_double) :: density, velocity(3)
  end type gm_rigid_def

  type, bind(c) :: gm_source_def
    integer(c_size_t) :: struct_size
    integer(c_int) :: material
    integer(c_size_t) :: count
    type(c_ptr) :: position
    real(c_double) :: velocity(3), point_size, density, start_time, period
    integer(c_int) :: max_injections
  end type gm_source_def

  type, bind(c) :: gm_sink_def
    integer(c_size_t) :: struct_size
    real(c_double) :: lower(3), upper(3)
  end type gm_sink_def

  type, bind(c) :: gm_flow_totals
    integer(c_size_t) :: struct_size
    real(c_double) :: mass
    integer(c_int64_t) :: points
  end type gm_flow_totals

  type, bind(c) :: gm_granular_def
    integer(c_size_t) :: struct_size
    real(c_double) :: critical_density, tolerance
    integer(c_int) :: density_control
  end type gm_granular_def

  type, bind(c) :: gm_granular_summary
    integer(c_size_t) :: struct_size
    integer(c_size_t) :: state_count(0:2)   ! by GM_STATE_*
    integer(c_size_t) :: component_count, layer_count
    integer(c_int) :: forest_reused
    real(c_double) :: geometry_seconds, pair_search_seconds, label_seconds, &
      layer_seconds, density_control_seconds
  end type gm_granular_summary

  type, bind(c) :: gm_points_def
    integer(c_size_t) :: struct_size, count
    integer(c_int) :: material
    type(c_ptr) :: position, velocity, volume, mass, density, domain_size, &
      stress
  end type gm_points_def

  type, bind(c) :: gm_fill_def
    integer(c_size_t) :: struct_size
    integer(c_int) :: material
    real(c_double) :: lower(3), upper(3)
    integer(c_int) :: points_per_cell_axis
    real(c_double) :: velocity(3), density
  end type gm_fill_def

  type, bind(c) :: gm_summary
    integer(c_size_t) :: struct_size
    real(c_double) :: mass, momentum(3), kinetic_energy, centre_of_mass(3)
  end type gm_summary

  type, bind(c) :: gm_allocator
    integer(c_size_t) :: struct_size
    type(c_funptr) :: malloc_fn, free_fn
    type(c_ptr) :: user
  end type gm_allocator

  type, bind(c) :: gm_drucker_prager_def
    integer(c_size_t) :: struct_size
    type(c_ptr) :: name
    real(c_double) :: youngs_modulus, poisson_ratio, density, friction_angle
  end type gm_drucker_prager_def

  type, bind(c) :: gm_filling_def
    integer(c_size_t) :: struct_size
    type(c_ptr) :: name
    real(c_double) :: density, poisson_ratio, kappa, void_ratio, &
      reference_pressure, bulk_viscosity, friction_angle, fluidity, &
      exponent, reference_stress, max_pressure
    integer(c_int) :: max_iterations
  end type gm_filling_def

  type, bind(c) :: gm_mohr_coulomb_def
    integer(c_size_t) :: struct_size
    type(c_ptr) :: name
    real(c_double) :: youngs_modulus, poisson_ratio, density, &
      friction_angle, dilation_angle, bagnold_viscosity
  end type gm_mohr_coulomb_def

  type, bind(c) :: gm_perzyna_def
    integer(c_size_t) :: struct_size
    type(c_ptr) :: name
    real(c_double) :: youngs_modulus, poisson_ratio, density, &
      friction_angle, fluidity, exponent, reference_stress
    integer(c_int) :: max_iterations, always_iterate
  end type gm_perzyna_def

  type, bind(c) :: gm_stress_free_def
    integer(c_size_t) :: struct_size
    type(c_ptr) :: name
    real(c_double) :: density, p_wave_modulus
  end type gm_stress_free_def

  type, bind(c) :: gm_von_mises_def
    integer(c_size_t) :: struct_size
    type(c_ptr) :: name
    real(c_double) :: youngs_modulus, poisson_ratio, density, yield_stress
  end type gm_von_mises_def

  type, bind(c) :: gm_mu_i_def
    integer(c_size_t) :: struct_size
    type(c_ptr) :: name
    real(c_double) :: youngs_modulus, poisson_ratio   ! Pa, -
    real(c_double) :: density, grain_density          ! kg/m^3
    real(c_double) :: grain_diameter                  ! m
    real(c_double) :: static_friction, limit_friction, inertial_number_scale
    real(c_double) :: critical_density                ! kg/m^3
    integer(c_int) :: regularise
    real(c_double) :: regularisation_exponent
  end type gm_mu_i_def

  interface
    function gm_version() bind(c, name="gm_version")
      import
      type(c_ptr) :: gm_version
    end function gm_version

    function gm_version_number() bind(c, name="gm_version_number")
      import
      integer(c_int) :: gm_version_number
    end function gm_version_number

    function gm_strerror(status) bind(c, name="gm_strerror")
      import
      type(c_ptr) :: gm_strerror
      integer(c_int), value :: status
    end function gm_strerror

    function gm_domain_def_init(out, struct_size) bind(c, name="gm_domain_def_init")
      import
      integer(c_int) :: gm_domain_def_init
      type(gm_domain_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_domain_def_init

    function gm_geometry_dimension(geometry) bind(c, name="gm_geometry_dimension")
      import
      integer(c_int) :: gm_geometry_dimension
      integer(c_int), value :: geometry
    end function gm_geometry_dimension

    function gm_domain_create(def, out) bind(c, name="gm_domain_create")
      import
      integer(c_int) :: gm_domain_create
      type(gm_domain_def), intent(in) :: def
      type(c_ptr), intent(out) :: out
    end function gm_domain_create

    function gm_last_create_error() bind(c, name="gm_last_create_error")
      import
      type(c_ptr) :: gm_last_create_error
    end function gm_last_create_error

    subroutine gm_domain_destroy(domain) bind(c, name="gm_domain_destroy")
      import
      type(c_ptr), value :: domain
    end subroutine gm_domain_destroy

    function gm_domain_last_error(domain) bind(c, name="gm_domain_last_error")
      import
      type(c_ptr) :: gm_domain_last_error
      type(c_ptr), value :: domain
    end function gm_domain_last_error

    function gm_material_def_init(out, struct_size) bind(c, name="gm_material_def_init")
      import
      integer(c_int) :: gm_material_def_init
      type(gm_material_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_material_def_init

    function gm_domain_add_material(domain, def, material_id) bind(c, name="gm_domain_add_material")
      import
      integer(c_int) :: gm_domain_add_material
      type(c_ptr), value :: domain
      type(gm_material_def), intent(in) :: def
      integer(c_int), intent(out) :: material_id
    end function gm_domain_add_material

    function gm_elastic_def_init(out, struct_size) bind(c, name="gm_elastic_def_init")
      import
      integer(c_int) :: gm_elastic_def_init
      type(gm_elastic_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_elastic_def_init

    function gm_domain_add_elastic(domain, def, material_id) bind(c, name="gm_domain_add_elastic")
      import
      integer(c_int) :: gm_domain_add_elastic
      type(c_ptr), value :: domain
      type(gm_elastic_def), intent(in) :: def
      integer(c_int), intent(out) :: material_id
    end function gm_domain_add_elastic

    function gm_elastic_update(batch, user, message, message_size) bind(c, name="gm_elastic_update")
      import
      integer(c_int) :: gm_elastic_update
      type(gm_material_batch), intent(in) :: batch
      type(c_ptr), value :: user
      character(kind=c_char), intent(out) :: message(*)
      integer(c_size_t), value :: message_size
    end function gm_elastic_update

    function gm_wall_def_init(out, struct_size) bind(c, name="gm_wall_def_init")
      import
      integer(c_int) :: gm_wall_def_init
      type(gm_wall_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_wall_def_init

    function gm_domain_add_wall(domain, def, wall_id) bind(c, name="gm_domain_add_wall")
      import
      integer(c_int) :: gm_domain_add_wall
      type(c_ptr), value :: domain
      type(gm_wall_def), intent(in) :: def
      integer(c_int), intent(out) :: wall_id
    end function gm_domain_add_wall

    function gm_wall_force_init(out, struct_size) bind(c, name="gm_wall_force_init")
      import
      integer(c_int) :: gm_wall_force_init
      type(gm_wall_force), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_wall_force_init

    function gm_domain_get_wall_force( &
        domain, wall_id, force) &
        bind(c, name="gm_domain_get_wall_force")
      import
      integer(c_int) :: gm_domain_get_wall_force
      type(c_ptr), value :: domain
      integer(c_int), value :: wall_id
      type(gm_wall_force), intent(inout) :: force
    end function gm_domain_get_wall_force

    function gm_domain_get_wall_tractions( &
        domain, wall_id, tractions, capacity, count) &
        bind(c, name="gm_domain_get_wall_tractions")
      import
      integer(c_int) :: gm_domain_get_wall_tractions
      type(c_ptr), value :: domain
      integer(c_int), value :: wall_id
      type(gm_wall_traction), intent(out) :: tractions(*)
      integer(c_size_t), value :: capacity
      integer(c_size_t), intent(out) :: count
    end function gm_domain_get_wall_tractions

    function gm_rigid_def_init(out, struct_size) bind(c, name="gm_rigid_def_init")
      import
      integer(c_int) :: gm_rigid_def_init
      type(gm_rigid_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_rigid_def_init

    function gm_domain_add_rigid(domain, def, material_id) bind(c, name="gm_domain_add_rigid")
      import
      integer(c_int) :: gm_domain_add_rigid
      type(c_ptr), value :: domain
      type(gm_rigid_def), intent(in) :: def
      integer(c_int), intent(out) :: material_id
    end function gm_domain_add_rigid

    function gm_domain_set_rigid_velocity( &
        domain, material_id, velocity) &
        bind(c, name="gm_domain_set_rigid_velocity")
      import
      integer(c_int) :: gm_domain_set_rigid_velocity
      type(c_ptr), value :: domain
      integer(c_int), value :: material_id
      real(c_double), intent(in) :: velocity(3)
    end function gm_domain_set_rigid_velocity

    function gm_domain_get_rigid_force( &
        domain, material_id, force) &
        bind(c, name="gm_domain_get_rigid_force")
      import
      integer(c_int) :: gm_domain_get_rigid_force
      type(c_ptr), value :: domain
      integer(c_int), value :: material_id
      real(c_double), intent(out) :: force(3)
    end function gm_domain_get_rigid_force

    function gm_rigid_load_init(out, struct_size) bind(c, name="gm_rigid_load_init")
      import
      integer(c_int) :: gm_rigid_load_init
      type(gm_rigid_load), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_rigid_load_init

    function gm_domain_get_rigid_load( &
        domain, material_id, load) &
        bind(c, name="gm_domain_get_rigid_load")
      import
      integer(c_int) :: gm_domain_get_rigid_load
      type(c_ptr), value :: domain
      integer(c_int), value :: material_id
      type(gm_rigid_load), intent(inout) :: load
    end function gm_domain_get_rigid_load

    function gm_domain_set_force_smoothing_time( &
        domain, seconds) &
        bind(c, name="gm_domain_set_force_smoothing_time")
      import
      integer(c_int) :: gm_domain_set_force_smoothing_time
      type(c_ptr), value :: domain
      real(c_double), value :: seconds
    end function gm_domain_set_force_smoothing_time

    function gm_domain_set_volumetric(domain, volumetric) &
        bind(c, name="gm_domain_set_volumetric")
      import
      integer(c_int) :: gm_domain_set_volumetric
      type(c_ptr), value :: domain
      integer(c_int), value :: volumetric
    end function gm_domain_set_volumetric

    function gm_source_def_init(out, struct_size) bind(c, name="gm_source_def_init")
      import
      integer(c_int) :: gm_source_def_init
      type(gm_source_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_source_def_init

    function gm_domain_add_source(domain, def, source_id) bind(c, name="gm_domain_add_source")
      import
      integer(c_int) :: gm_domain_add_source
      type(c_ptr), value :: domain
      type(gm_source_def), intent(in) :: def
      integer(c_int), intent(out) :: source_id
    end function gm_domain_add_source

    function gm_sink_def_init(out, struct_size) bind(c, name="gm_sink_def_init")
      import
      integer(c_int) :: gm_sink_def_init
      type(gm_sink_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_sink_def_init

    function gm_domain_add_sink(domain, def, sink_id) bind(c, name="gm_domain_add_sink")
      import
      integer(c_int) :: gm_domain_add_sink
      type(c_ptr), value :: domain
      type(gm_sink_def), intent(in) :: def
      integer(c_int), intent(out) :: sink_id
    end function gm_domain_add_sink

    function gm_flow_totals_init(out, struct_size) bind(c, name="gm_flow_totals_init")
      import
      integer(c_int) :: gm_flow_totals_init
      type(gm_flow_totals), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_flow_totals_init

    function gm_domain_get_source_totals( &
        domain, source_id, totals) &
        bind(c, name="gm_domain_get_source_totals")
      import
      integer(c_int) :: gm_domain_get_source_totals
      type(c_ptr), value :: domain
      integer(c_int), value :: source_id
      type(gm_flow_totals), intent(inout) :: totals
    end function gm_domain_get_source_totals

    function gm_domain_get_sink_totals( &
        domain, sink_id, totals) &
        bind(c, name="gm_domain_get_sink_totals")
      import
      integer(c_int) :: gm_domain_get_sink_totals
      type(c_ptr), value :: domain
      integer(c_int), value :: sink_id
      type(gm_flow_totals), intent(inout) :: totals
    end function gm_domain_get_sink_totals

    function gm_granular_def_init(out, struct_size) bind(c, name="gm_granular_def_init")
      import
      integer(c_int) :: gm_granular_def_init
      type(gm_granular_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_granular_def_init

    function gm_domain_set_granular(domain, material, def) bind(c, name="gm_domain_set_granular")
      import
      integer(c_int) :: gm_domain_set_granular
      type(c_ptr), value :: domain
      integer(c_int), value :: material
      type(gm_granular_def), intent(in) :: def
    end function gm_domain_set_granular

    function gm_granular_summary_init(out, struct_size) bind(c, name="gm_granular_summary_init")
      import
      integer(c_int) :: gm_granular_summary_init
      type(gm_granular_summary), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_granular_summary_init

    function gm_domain_get_granular_summary( &
        domain, summary) &
        bind(c, name="gm_domain_get_granular_summary")
      import
      integer(c_int) :: gm_domain_get_granular_summary
      type(c_ptr), value :: domain
      type(gm_granular_summary), intent(inout) :: summary
    end function gm_domain_get_granular_summary

    function gm_points_def_init(out, struct_size) bind(c, name="gm_points_def_init")
      import
      integer(c_int) :: gm_points_def_init
      type(gm_points_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_points_def_init

    function gm_domain_add_points(domain, def, first_id) bind(c, name="gm_domain_add_points")
      import
      integer(c_int) :: gm_domain_add_points
      type(c_ptr), value :: domain
      type(gm_points_def), intent(in) :: def
      integer(c_int64_t), intent(out) :: first_id
    end function gm_domain_add_points

    function gm_fill_def_init(out, struct_size) bind(c, name="gm_fill_def_init")
      import
      integer(c_int) :: gm_fill_def_init
      type(gm_fill_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_fill_def_init

    function gm_domain_fill_box(domain, def, first_id, count) bind(c, name="gm_domain_fill_box")
      import
      integer(c_int) :: gm_domain_fill_box
      type(c_ptr), value :: domain
      type(gm_fill_def), intent(in) :: def
      integer(c_int64_t), intent(out) :: first_id
      integer(c_size_t), intent(out) :: count
    end function gm_domain_fill_box

    function gm_domain_point_count(domain) bind(c, name="gm_domain_point_count")
      import
      integer(c_size_t) :: gm_domain_point_count
      type(c_ptr), value :: domain
    end function gm_domain_point_count

    function gm_domain_field_components( &
        domain, field, components) &
        bind(c, name="gm_domain_field_components")
      import
      integer(c_int) :: gm_domain_field_components
      type(c_ptr), value :: domain
      integer(c_int), value :: field
      integer(c_size_t), intent(out) :: components
    end function gm_domain_field_components

    function gm_domain_get_field(domain, field, out, out_length) bind(c, name="gm_domain_get_field")
      import
      integer(c_int) :: gm_domain_get_field
      type(c_ptr), value :: domain
      integer(c_int), value :: field
      real(c_double), intent(out) :: out(*)
      integer(c_size_t), value :: out_length
    end function gm_domain_get_field

    function gm_domain_set_field(domain, field, values, length) bind(c, name="gm_domain_set_field")
      import
      integer(c_int) :: gm_domain_set_field
      type(c_ptr), value :: domain
      integer(c_int), value :: field
      real(c_double), intent(in) :: values(*)
      integer(c_size_t), value :: length
    end function gm_domain_set_field

    function gm_domain_get_ids(domain, out, out_length) bind(c, name="gm_domain_get_ids")
      import
      integer(c_int) :: gm_domain_get_ids
      type(c_ptr), value :: domain
      integer(c_int64_t), intent(out) :: out(*)
      integer(c_size_t), value :: out_length
    end function gm_domain_get_ids

    function gm_domain_point_index(domain, id, index) bind(c, name="gm_domain_point_index")
      import
      integer(c_int) :: gm_domain_point_index
      type(c_ptr), value :: domain
      integer(c_int64_t), value :: id
      integer(c_size_t), intent(out) :: index
    end function gm_domain_point_index

    function gm_domain_view_field( &
        domain, field, component, data) &
        bind(c, name="gm_domain_view_field")
      import
      integer(c_int) :: gm_domain_view_field
      type(c_ptr), value :: domain
      integer(c_int), value :: field
      integer(c_size_t), value :: component
      type(c_ptr), intent(out) :: data
    end function gm_domain_view_field

    function gm_domain_edit_field( &
        domain, field, component, data) &
        bind(c, name="gm_domain_edit_field")
      import
      integer(c_int) :: gm_domain_edit_field
      type(c_ptr), value :: domain
      integer(c_int), value :: field
      integer(c_size_t), value :: component
      type(c_ptr), intent(out) :: data
    end function gm_domain_edit_field

    function gm_domain_view_ids(domain, ids) bind(c, name="gm_domain_view_ids")
      import
      integer(c_int) :: gm_domain_view_ids
      type(c_ptr), value :: domain
      type(c_ptr), intent(out) :: ids
    end function gm_domain_view_ids

    function gm_domain_set_step_hook(domain, hook, user) bind(c, name="gm_domain_set_step_hook")
      import
      integer(c_int) :: gm_domain_set_step_hook
      type(c_ptr), value :: domain
      type(c_funptr), value :: hook
      type(c_ptr), value :: user
    end function gm_domain_set_step_hook

    function gm_domain_step(domain, dt) bind(c, name="gm_domain_step")
      import
      integer(c_int) :: gm_domain_step
      type(c_ptr), value :: domain
      real(c_double), value :: dt
    end function gm_domain_step

    function gm_domain_stable_dt(domain, dt) bind(c, name="gm_domain_stable_dt")
      import
      integer(c_int) :: gm_domain_stable_dt
      type(c_ptr), value :: domain
      real(c_double), intent(out) :: dt
    end function gm_domain_stable_dt

    function gm_domain_get_time(domain, time, step_count) bind(c, name="gm_domain_get_time")
      import
      integer(c_int) :: gm_domain_get_time
      type(c_ptr), value :: domain
      real(c_double), intent(out) :: time
      integer(c_int64_t), intent(out) :: step_count
    end function gm_domain_get_time

    function gm_summary_init(out, struct_size) bind(c, name="gm_summary_init")
      import
      integer(c_int) :: gm_summary_init
      type(gm_summary), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_summary_init

    function gm_domain_get_summary(domain, summary) bind(c, name="gm_domain_get_summary")
      import
      integer(c_int) :: gm_domain_get_summary
      type(c_ptr), value :: domain
      type(gm_summary), intent(inout) :: summary
    end function gm_domain_get_summary

    function gm_domain_write_vtu(domain, path) bind(c, name="gm_domain_write_vtu")
      import
      integer(c_int) :: gm_domain_write_vtu
      type(c_ptr), value :: domain
      character(kind=c_char), intent(in) :: path(*)
    end function gm_domain_write_vtu

    function gm_series_create(pvd_path, out) bind(c, name="gm_series_create")
      import
      integer(c_int) :: gm_series_create
      character(kind=c_char), intent(in) :: pvd_path(*)
      type(c_ptr), intent(out) :: out
    end function gm_series_create

    function gm_series_write(series, domain) bind(c, name="gm_series_write")
      import
      integer(c_int) :: gm_series_write
      type(c_ptr), value :: series
      type(c_ptr), value :: domain
    end function gm_series_write

    function gm_domain_write_domains_vtu(domain, path) bind(c, name="gm_domain_write_domains_vtu")
      import
      integer(c_int) :: gm_domain_write_domains_vtu
      type(c_ptr), value :: domain
      character(kind=c_char), intent(in) :: path(*)
    end function gm_domain_write_domains_vtu

    function gm_series_set_domains(series, enabled) bind(c, name="gm_series_set_domains")
      import
      integer(c_int) :: gm_series_set_domains
      type(c_ptr), value :: series
      integer(c_int), value :: enabled
    end function gm_series_set_domains

    subroutine gm_series_destroy(series) bind(c, name="gm_series_destroy")
      import
      type(c_ptr), value :: series
    end subroutine gm_series_destroy

    function gm_domain_advance( &
        domain, end_time, dt, progress, user) &
        bind(c, name="gm_domain_advance")
      import
      integer(c_int) :: gm_domain_advance
      type(c_ptr), value :: domain
      real(c_double), value :: end_time
      real(c_double), value :: dt
      type(c_funptr), value :: progress
      type(c_ptr), value :: user
    end function gm_domain_advance

    function gm_domain_save(domain, path) bind(c, name="gm_domain_save")
      import
      integer(c_int) :: gm_domain_save
      type(c_ptr), value :: domain
      character(kind=c_char), intent(in) :: path(*)
    end function gm_domain_save

    function gm_domain_load(domain, path) bind(c, name="gm_domain_load")
      import
      integer(c_int) :: gm_domain_load
      type(c_ptr), value :: domain
      character(kind=c_char), intent(in) :: path(*)
    end function gm_domain_load

    function gm_set_allocator(allocator) bind(c, name="gm_set_allocator")
      import
      integer(c_int) :: gm_set_allocator
      type(gm_allocator), intent(in) :: allocator
    end function gm_set_allocator

    function gm_drucker_prager_def_init(out, struct_size) bind(c, name="gm_drucker_prager_def_init")
      import
      integer(c_int) :: gm_drucker_prager_def_init
      type(gm_drucker_prager_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_drucker_prager_def_init

    function gm_domain_add_drucker_prager( &
        domain, def, material_id) &
        bind(c, name="gm_domain_add_drucker_prager")
      import
      integer(c_int) :: gm_domain_add_drucker_prager
      type(c_ptr), value :: domain
      type(gm_drucker_prager_def), intent(in) :: def
      integer(c_int), intent(out) :: material_id
    end function gm_domain_add_drucker_prager

    function gm_drucker_prager_update( &
        batch, user, message, message_size) &
        bind(c, name="gm_drucker_prager_update")
      import
      integer(c_int) :: gm_drucker_prager_update
      type(gm_material_batch), intent(in) :: batch
      type(c_ptr), value :: user
      character(kind=c_char), intent(out) :: message(*)
      integer(c_size_t), value :: message_size
    end function gm_drucker_prager_update

    function gm_filling_def_init(out, struct_size) bind(c, name="gm_filling_def_init")
      import
      integer(c_int) :: gm_filling_def_init
      type(gm_filling_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_filling_def_init

    function gm_domain_add_filling(domain, def, material_id) bind(c, name="gm_domain_add_filling")
      import
      integer(c_int) :: gm_domain_add_filling
      type(c_ptr), value :: domain
      type(gm_filling_def), intent(in) :: def
      integer(c_int), intent(out) :: material_id
    end function gm_domain_add_filling

    function gm_filling_update(batch, user, message, message_size) bind(c, name="gm_filling_update")
      import
      integer(c_int) :: gm_filling_update
      type(gm_material_batch), intent(in) :: batch
      type(c_ptr), value :: user
      character(kind=c_char), intent(out) :: message(*)
      integer(c_size_t), value :: message_size
    end function gm_filling_update

    function gm_mohr_coulomb_def_init(out, struct_size) bind(c, name="gm_mohr_coulomb_def_init")
      import
      integer(c_int) :: gm_mohr_coulomb_def_init
      type(gm_mohr_coulomb_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_mohr_coulomb_def_init

    function gm_domain_add_mohr_coulomb( &
        domain, def, material_id) &
        bind(c, name="gm_domain_add_mohr_coulomb")
      import
      integer(c_int) :: gm_domain_add_mohr_coulomb
      type(c_ptr), value :: domain
      type(gm_mohr_coulomb_def), intent(in) :: def
      integer(c_int), intent(out) :: material_id
    end function gm_domain_add_mohr_coulomb

    function gm_mohr_coulomb_update( &
        batch, user, message, message_size) &
        bind(c, name="gm_mohr_coulomb_update")
      import
      integer(c_int) :: gm_mohr_coulomb_update
      type(gm_material_batch), intent(in) :: batch
      type(c_ptr), value :: user
      character(kind=c_char), intent(out) :: message(*)
      integer(c_size_t), value :: message_size
    end function gm_mohr_coulomb_update

    function gm_perzyna_def_init(out, struct_size) bind(c, name="gm_perzyna_def_init")
      import
      integer(c_int) :: gm_perzyna_def_init
      type(gm_perzyna_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_perzyna_def_init

    function gm_domain_add_perzyna(domain, def, material_id) bind(c, name="gm_domain_add_perzyna")
      import
      integer(c_int) :: gm_domain_add_perzyna
      type(c_ptr), value :: domain
      type(gm_perzyna_def), intent(in) :: def
      integer(c_int), intent(out) :: material_id
    end function gm_domain_add_perzyna

    function gm_perzyna_update(batch, user, message, message_size) bind(c, name="gm_perzyna_update")
      import
      integer(c_int) :: gm_perzyna_update
      type(gm_material_batch), intent(in) :: batch
      type(c_ptr), value :: user
      character(kind=c_char), intent(out) :: message(*)
      integer(c_size_t), value :: message_size
    end function gm_perzyna_update

    function gm_stress_free_def_init(out, struct_size) bind(c, name="gm_stress_free_def_init")
      import
      integer(c_int) :: gm_stress_free_def_init
      type(gm_stress_free_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_stress_free_def_init

    function gm_domain_add_stress_free( &
        domain, def, material_id) &
        bind(c, name="gm_domain_add_stress_free")
      import
      integer(c_int) :: gm_domain_add_stress_free
      type(c_ptr), value :: domain
      type(gm_stress_free_def), intent(in) :: def
      integer(c_int), intent(out) :: material_id
    end function gm_domain_add_stress_free

    function gm_stress_free_update( &
        batch, user, message, message_size) &
        bind(c, name="gm_stress_free_update")
      import
      integer(c_int) :: gm_stress_free_update
      type(gm_material_batch), intent(in) :: batch
      type(c_ptr), value :: user
      character(kind=c_char), intent(out) :: message(*)
      integer(c_size_t), value :: message_size
    end function gm_stress_free_update

    function gm_von_mises_def_init(out, struct_size) bind(c, name="gm_von_mises_def_init")
      import
      integer(c_int) :: gm_von_mises_def_init
      type(gm_von_mises_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_von_mises_def_init

    function gm_domain_add_von_mises( &
        domain, def, material_id) &
        bind(c, name="gm_domain_add_von_mises")
      import
      integer(c_int) :: gm_domain_add_von_mises
      type(c_ptr), value :: domain
      type(gm_von_mises_def), intent(in) :: def
      integer(c_int), intent(out) :: material_id
    end function gm_domain_add_von_mises

    function gm_von_mises_update( &
        batch, user, message, message_size) &
        bind(c, name="gm_von_mises_update")
      import
      integer(c_int) :: gm_von_mises_update
      type(gm_material_batch), intent(in) :: batch
      type(c_ptr), value :: user
      character(kind=c_char), intent(out) :: message(*)
      integer(c_size_t), value :: message_size
    end function gm_von_mises_update

    function gm_mu_i_def_init(out, struct_size) bind(c, name="gm_mu_i_def_init")
      import
      integer(c_int) :: gm_mu_i_def_init
      type(gm_mu_i_def), intent(inout) :: out
      integer(c_size_t), value :: struct_size
    end function gm_mu_i_def_init

    function gm_domain_add_mu_i( &
        domain, def, material_id) &
        bind(c, name="gm_domain_add_mu_i")
      import
      integer(c_int) :: gm_domain_add_mu_i
      type(c_ptr), value :: domain
      type(gm_mu_i_def), intent(in) :: def
      integer(c_int), intent(out) :: material_id
    end function gm_domain_add_mu_i

    function gm_mu_i_update( &
        batch, user, message, message_size) &
        bind(c, name="gm_mu_i_update")
      import
      integer(c_int) :: gm_mu_i_update
      type(gm_material_batch), intent(in) :: batch
      type(c_ptr), value :: user
      character(kind=c_char), intent(out) :: message(*)
      integer(c_size_t), value :: message_size
    end function gm_mu_i_update
  end interface
end module granmpm
