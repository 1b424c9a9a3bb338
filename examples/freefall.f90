! freefall.f90 - libgranmpm from Fortran (module granmpm): an elastic
! block falls freely in plane strain, far from every face of the grid, and
! every point's vertical velocity must equal g t.
!
! Also checks that the module's bind(c) types have the library's sizes:
! gm_*_init sets struct_size to the bytes the library filled, and refuses
! a size it does not know, so a type shorter or longer than its C
! structure fails here.
!
! Build against an installed libgranmpm (the module was compiled with the
! same Fortran compiler):
!   gfortran freefall.f90 $(pkg-config --cflags --libs granmpm)
! Exit status 0 when every check holds.
!
! SPDX-License-Identifier: BSD-2-Clause
program freefall
  use, intrinsic :: iso_c_binding
  use granmpm
  implicit none

  ! Numbers exact in binary, as in .ci/consumer.c.
  real(c_double), parameter :: cell = 0.125d0      ! m
  real(c_double), parameter :: gravity_y = -9.75d0 ! m/s^2
  real(c_double), parameter :: dt = 1d-3           ! s, below the stable ~1.7 ms
  integer, parameter :: steps = 10

  type(gm_domain_def) :: def
  type(gm_elastic_def) :: elastic
  type(gm_fill_def) :: fill
  type(gm_summary) :: summary
  type(c_ptr) :: domain
  integer(c_int) :: status, material
  integer(c_int64_t) :: first_id
  integer(c_size_t) :: count, components
  real(c_double), allocatable :: velocity(:)
  real(c_double) :: expected, worst
  integer :: step, failures

  failures = 0
  call check_sizes()

  status = gm_domain_def_init(def, c_sizeof(def))
  call expect(status == GM_OK, "gm_domain_def_init")
  ! Defaults written by the library, read through this module's layout: a
  ! field at a wrong offset reads a wrong value.
  call expect(def%geometry == GM_GEOMETRY_PLANE_STRAIN, "default geometry")
  call expect(def%cell_size == 0.1d0, "default cell_size")
  call expect(def%cfl == 0.5d0 .and. def%max_retries == 4 &
    .and. def%worker_count == 1, "default cfl, max_retries, worker_count")
  call expect(def%walls(GM_FACE_YMIN) == GM_WALL_OPEN &
    .and. def%pic_fraction == 0d0, "default walls, pic_fraction")
  def%extent(1:2) = 1d0
  def%cell_size = cell
  def%gravity(2) = gravity_y
  status = gm_domain_create(def, domain)
  call expect_ok(status, "gm_domain_create")
  if (status /= GM_OK) stop 1

  status = gm_elastic_def_init(elastic, c_sizeof(elastic))
  call expect(elastic%youngs_modulus == 1d6 .and. elastic%poisson_ratio == &
    0.3d0 .and. elastic%density == 1000d0, "default elastic material")
  call expect_ok(gm_domain_add_elastic(domain, elastic, material), &
    "gm_domain_add_elastic")

  status = gm_fill_def_init(fill, c_sizeof(fill))
  call expect(fill%points_per_cell_axis == 2, "default points_per_cell_axis")
  fill%material = material
  fill%lower(1:2) = 0.25d0
  fill%upper(1:2) = 0.75d0
  call expect_ok(gm_domain_fill_box(domain, fill, first_id, count), &
    "gm_domain_fill_box")
  call expect(count == 64, "64 points (8 x 8)")

  do step = 1, steps
    call expect_ok(gm_domain_step(domain, dt), "gm_domain_step")
  end do

  ! Far from every face only gravity acts and the internal forces of a
  ! stress-free falling block vanish, so each point's velocity is
  ! g t = -9.75 * 0.01 m/s; 1e-12 relative allows the rounding of ten
  ! FLIP updates.
  call expect_ok(gm_domain_field_components(domain, GM_FIELD_VELOCITY, &
    components), "gm_domain_field_components")
  allocate (velocity(components * count))
  call expect_ok(gm_domain_get_field(domain, GM_FIELD_VELOCITY, velocity, &
    size(velocity, kind=c_size_t)), "gm_domain_get_field")
  expected = gravity_y * dt * steps
  worst = maxval(abs(velocity(2::2) - expected))
  call expect(worst <= 1d-12 * abs(expected), "v_y = g t for every point")
  call expect(maxval(abs(velocity(1::2))) <= 1d-12, "v_x = 0")

  status = gm_summary_init(summary, c_sizeof(summary))
  call expect_ok(gm_domain_get_summary(domain, summary), &
    "gm_domain_get_summary")
  ! 0.25 m^2 at 1000 kg/m^3 = 250 kg per metre of thickness.
  call expect(abs(summary%mass - 250d0) <= 1d-12 * 250d0, "mass 250 kg/m")

  call gm_domain_destroy(domain)
  print '(a, es23.16, a, es9.2)', "freefall: v_y = ", expected, &
    " m/s at t = 0.01 s; largest deviation ", worst
  if (failures /= 0) then
    print '(a, i0, a)', "freefall: ", failures, " check(s) failed"
    stop 1
  end if
  print '(a)', "freefall: all checks passed"

contains

  subroutine expect(condition, what)
    logical, intent(in) :: condition
    character(*), intent(in) :: what
    if (.not. condition) then
      print '(2a)', "freefall: FAILED: ", what
      failures = failures + 1
    end if
  end subroutine expect

  subroutine expect_ok(code, call_name)
    integer(c_int), intent(in) :: code
    character(*), intent(in) :: call_name
    character(kind=c_char), pointer :: text(:)
    if (code == GM_OK) return
    call c_f_pointer(gm_strerror(code), text, [256])
    print '(3a)', "freefall: FAILED: ", call_name, ": " // &
      c_string(text)
    failures = failures + 1
  end subroutine expect_ok

  ! The Fortran text of a NUL-terminated C string (at most 256 characters).
  function c_string(text) result(string)
    character(kind=c_char), intent(in) :: text(:)
    character(:), allocatable :: string
    integer :: n
    n = 0
    do while (n < size(text))
      if (text(n + 1) == c_null_char) exit
      n = n + 1
    end do
    allocate (character(n) :: string)
    string = transfer(text(1:n), string)
  end function c_string

  ! Every structure the library initialises: the library's size must be
  ! this module's c_sizeof.
  subroutine check_sizes()
    type(gm_domain_def) :: a
    type(gm_material_def) :: b
    type(gm_elastic_def) :: c
    type(gm_wall_def) :: d
    type(gm_wall_force) :: e
    type(gm_rigid_def) :: f
    type(gm_source_def) :: g
    type(gm_sink_def) :: h
    type(gm_flow_totals) :: i
    type(gm_granular_def) :: j
    type(gm_granular_summary) :: k
    type(gm_points_def) :: l
    type(gm_fill_def) :: m
    type(gm_summary) :: n
    type(gm_drucker_prager_def) :: o
    type(gm_filling_def) :: p
    type(gm_mohr_coulomb_def) :: q
    type(gm_perzyna_def) :: r
    type(gm_stress_free_def) :: s
    type(gm_von_mises_def) :: t
    type(gm_rigid_load) :: u
    type(gm_mu_i_def) :: w
    call size_ok(gm_domain_def_init(a, c_sizeof(a)), a%struct_size, &
      c_sizeof(a), "gm_domain_def")
    call size_ok(gm_material_def_init(b, c_sizeof(b)), b%struct_size, &
      c_sizeof(b), "gm_material_def")
    call size_ok(gm_elastic_def_init(c, c_sizeof(c)), c%struct_size, &
      c_sizeof(c), "gm_elastic_def")
    call size_ok(gm_wall_def_init(d, c_sizeof(d)), d%struct_size, &
      c_sizeof(d), "gm_wall_def")
    call size_ok(gm_wall_force_init(e, c_sizeof(e)), e%struct_size, &
      c_sizeof(e), "gm_wall_force")
    call size_ok(gm_rigid_load_init(u, c_sizeof(u)), u%struct_size, &
      c_sizeof(u), "gm_rigid_load")
    call size_ok(gm_mu_i_def_init(w, c_sizeof(w)), w%struct_size, &
      c_sizeof(w), "gm_mu_i_def")
    call size_ok(gm_rigid_def_init(f, c_sizeof(f)), f%struct_size, &
      c_sizeof(f), "gm_rigid_def")
    call size_ok(gm_source_def_init(g, c_sizeof(g)), g%struct_size, &
      c_sizeof(g), "gm_source_def")
    call size_ok(gm_sink_def_init(h, c_sizeof(h)), h%struct_size, &
      c_sizeof(h), "gm_sink_def")
    call size_ok(gm_flow_totals_init(i, c_sizeof(i)), i%struct_size, &
      c_sizeof(i), "gm_flow_totals")
    call size_ok(gm_granular_def_init(j, c_sizeof(j)), j%struct_size, &
      c_sizeof(j), "gm_granular_def")
    call size_ok(gm_granular_summary_init(k, c_sizeof(k)), k%struct_size, &
      c_sizeof(k), "gm_granular_summary")
    call size_ok(gm_points_def_init(l, c_sizeof(l)), l%struct_size, &
      c_sizeof(l), "gm_points_def")
    call size_ok(gm_fill_def_init(m, c_sizeof(m)), m%struct_size, &
      c_sizeof(m), "gm_fill_def")
    call size_ok(gm_summary_init(n, c_sizeof(n)), n%struct_size, &
      c_sizeof(n), "gm_summary")
    call size_ok(gm_drucker_prager_def_init(o, c_sizeof(o)), o%struct_size, &
      c_sizeof(o), "gm_drucker_prager_def")
    call size_ok(gm_filling_def_init(p, c_sizeof(p)), p%struct_size, &
      c_sizeof(p), "gm_filling_def")
    call size_ok(gm_mohr_coulomb_def_init(q, c_sizeof(q)), q%struct_size, &
      c_sizeof(q), "gm_mohr_coulomb_def")
    call size_ok(gm_perzyna_def_init(r, c_sizeof(r)), r%struct_size, &
      c_sizeof(r), "gm_perzyna_def")
    call size_ok(gm_stress_free_def_init(s, c_sizeof(s)), s%struct_size, &
      c_sizeof(s), "gm_stress_free_def")
    call size_ok(gm_von_mises_def_init(t, c_sizeof(t)), t%struct_size, &
      c_sizeof(t), "gm_von_mises_def")
    ! Last fields of the material types, read through this module.
    call expect(q%bagnold_viscosity == 0.15d0 .and. q%youngs_modulus == &
      1d9, "gm_mohr_coulomb_def defaults (000 Table 3)")
    call expect(r%max_iterations == 60 .and. r%always_iterate == 0, &
      "gm_perzyna_def defaults")
    call expect(p%max_iterations == 60 .and. p%max_pressure == 1d5, &
      "gm_filling_def defaults")
    call expect(t%yield_stress == 2d7 .and. o%friction_angle > 0.436d0 &
      .and. o%friction_angle < 0.437d0, "von Mises, Drucker-Prager defaults")
    call expect(j%tolerance == 1d-6 .and. d%normal(2) == 1d0 .and. &
      f%density == 1000d0, "granular, wall, rigid defaults")
  end subroutine check_sizes

  subroutine size_ok(code, library_size, module_size, name)
    integer(c_int), intent(in) :: code
    integer(c_size_t), intent(in) :: library_size, module_size
    character(*), intent(in) :: name
    if (code /= GM_OK .or. library_size /= module_size) then
      print '(3a, i0, a, i0, a, i0)', "freefall: FAILED: ", name, &
        ": status ", code, ", library size ", library_size, &
        ", module size ", module_size
      failures = failures + 1
    end if
  end subroutine size_ok
end program freefall
