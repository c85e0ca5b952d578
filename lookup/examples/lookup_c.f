!     lookup_c: ISO_C_BINDING interface to the C ABI of the lookup
!     library (lookup/include/lookup.h). Fixed form, columns 7-72, so
!     that it can be compiled with Abaqus/CalculiX user subroutines.
!     Used by abaqus_gapcon.f and calculix_gapcon.f.
!
!     Units: SI (Pa, W/m^2, K, W/(m^2 K)). Every function returning an
!     integer(c_int32_t) returns a status code, LOOKUP_OK = 0.
      module lookup_c
      use, intrinsic :: iso_c_binding
      implicit none
!
!     Status codes (lookup.h).
      integer(c_int32_t), parameter :: LOOKUP_OK = 0
      integer(c_int32_t), parameter :: LOOKUP_ERR_NULL_ARGUMENT = 1
      integer(c_int32_t), parameter :: LOOKUP_ERR_IO = 2
      integer(c_int32_t), parameter :: LOOKUP_ERR_FORMAT = 3
      integer(c_int32_t), parameter :: LOOKUP_ERR_VERSION = 4
      integer(c_int32_t), parameter :: LOOKUP_ERR_CHECKSUM = 5
      integer(c_int32_t), parameter :: LOOKUP_ERR_INVALID_ARGUMENT = 6
      integer(c_int32_t), parameter :: LOOKUP_ERR_NON_FINITE = 7
      integer(c_int32_t), parameter :: LOOKUP_ERR_INVALID_QUERY = 8
      integer(c_int32_t), parameter :: LOOKUP_ERR_OUT_OF_RANGE = 9
      integer(c_int32_t), parameter :: LOOKUP_ERR_VANISHING_JUMP = 10
      integer(c_int32_t), parameter :: LOOKUP_ERR_NON_FINITE_RESULT = 11
      integer(c_int32_t), parameter :: LOOKUP_ERR_PANIC = 12
      integer(c_int32_t), parameter :: LOOKUP_ERR_MATERIAL_MISMATCH=13
!
!     Axis and extrapolation codes.
      integer(c_int32_t), parameter :: LOOKUP_AXIS_ALL = -1
      integer(c_int32_t), parameter :: LOOKUP_AXIS_PRESSURE = 0
      integer(c_int32_t), parameter :: LOOKUP_AXIS_FLUX = 1
      integer(c_int32_t), parameter :: LOOKUP_AXIS_TEMPERATURE = 2
      integer(c_int32_t), parameter :: LOOKUP_EXTRAPOLATE_ERROR = 0
      integer(c_int32_t), parameter :: LOOKUP_EXTRAPOLATE_CLAMP = 1
      integer(c_int32_t), parameter :: LOOKUP_EXTRAPOLATE_LINEAR = 2
      integer(c_int32_t), parameter :: LOOKUP_EXTRAPOLATE_POWER = 3
!
!     Bits of the flags fields (test with iand).
      integer(c_int32_t), parameter :: LOOKUP_FLAG_EXTRAP_PRESSURE = 1
      integer(c_int32_t), parameter :: LOOKUP_FLAG_EXTRAP_FLUX = 2
      integer(c_int32_t), parameter :: LOOKUP_FLAG_EXTRAP_TEMP = 4
      integer(c_int32_t), parameter :: LOOKUP_FLAG_EXTRAPOLATED = 7
      integer(c_int32_t), parameter :: LOOKUP_FLAG_CAPPED = 8
      integer(c_int32_t), parameter :: LOOKUP_FLAG_NO_ERROR_EST = 16
!
!     Body codes of lookup_law_check_material.
      integer(c_int32_t), parameter :: LOOKUP_BODY_UPPER = 1
      integer(c_int32_t), parameter :: LOOKUP_BODY_LOWER = 2
!
!     struct lookup_value: the law at (p, |h|, theta).
      type, bind(c) :: lookup_value
        real(c_double) :: flux, jump, jump_std, jump_error
        real(c_double) :: d_jump_dp, d_jump_dh, d_jump_dtheta
        real(c_double) :: conductance, d_conductance_dp
        real(c_double) :: d_conductance_dh, d_conductance_dtheta
        integer(c_int32_t) :: flags, reserved
      end type lookup_value
!
!     struct lookup_flux_value: the law at (p, jump, theta).
      type, bind(c) :: lookup_flux_value
        real(c_double) :: flux, jump_std, jump_error, conductance
        real(c_double) :: d_flux_dp, d_flux_djump, d_flux_dtheta
        real(c_double) :: d_conductance_dp, d_conductance_djump
        real(c_double) :: d_conductance_dtheta
        integer(c_int32_t) :: flags, reserved
      end type lookup_flux_value
!
      interface
!       lookup_law *lookup_law_open(const char *path, int32_t *status)
        function lookup_law_open(path, status)
     &      bind(c, name='lookup_law_open')
          import :: c_ptr, c_char, c_int32_t
          character(kind=c_char), dimension(*), intent(in) :: path
          integer(c_int32_t), intent(out) :: status
          type(c_ptr) :: lookup_law_open
        end function lookup_law_open
!
        function lookup_law_eval(law, p, h, theta, val)
     &      bind(c, name='lookup_law_eval')
          import :: c_ptr, c_double, c_int32_t, lookup_value
          type(c_ptr), value :: law
          real(c_double), value :: p, h, theta
          type(lookup_value), intent(out) :: val
          integer(c_int32_t) :: lookup_law_eval
        end function lookup_law_eval
!
        function lookup_law_eval_at_jump(law, p, jump, theta, val)
     &      bind(c, name='lookup_law_eval_at_jump')
          import :: c_ptr, c_double, c_int32_t, lookup_flux_value
          type(c_ptr), value :: law
          real(c_double), value :: p, jump, theta
          type(lookup_flux_value), intent(out) :: val
          integer(c_int32_t) :: lookup_law_eval_at_jump
        end function lookup_law_eval_at_jump
!
        function lookup_law_set_extrapolation(law, axis, policy)
     &      bind(c, name='lookup_law_set_extrapolation')
          import :: c_ptr, c_int32_t
          type(c_ptr), value :: law
          integer(c_int32_t), value :: axis, policy
          integer(c_int32_t) :: lookup_law_set_extrapolation
        end function lookup_law_set_extrapolation
!
        function lookup_law_set_max_conductance(law, k_max)
     &      bind(c, name='lookup_law_set_max_conductance')
          import :: c_ptr, c_double, c_int32_t
          type(c_ptr), value :: law
          real(c_double), value :: k_max
          integer(c_int32_t) :: lookup_law_set_max_conductance
        end function lookup_law_set_max_conductance
!
        function lookup_law_check_material(law, body, props, rel_tol)
     &      bind(c, name='lookup_law_check_material')
          import :: c_ptr, c_double, c_int32_t
          type(c_ptr), value :: law
          integer(c_int32_t), value :: body
          real(c_double), dimension(6), intent(in) :: props
          real(c_double), value :: rel_tol
          integer(c_int32_t) :: lookup_law_check_material
        end function lookup_law_check_material
!
        subroutine lookup_law_free(law)
     &      bind(c, name='lookup_law_free')
          import :: c_ptr
          type(c_ptr), value :: law
        end subroutine lookup_law_free
!
!       size_t lookup_last_error(char *buf, size_t len)
        function lookup_last_error(buf, len)
     &      bind(c, name='lookup_last_error')
          import :: c_char, c_size_t
          character(kind=c_char), dimension(*) :: buf
          integer(c_size_t), value :: len
          integer(c_size_t) :: lookup_last_error
        end function lookup_last_error
      end interface
!
      contains
!
!     The last error message of this thread as a Fortran string.
      function lookup_message() result(msg)
      character(len=256) :: msg
      character(kind=c_char) :: buf(256)
      integer(c_size_t) :: n
      integer :: i
      msg = ' '
      n = lookup_last_error(buf, int(256, c_size_t))
      do i = 1, int(min(n, int(255, c_size_t)))
        msg(i:i) = buf(i)
      end do
      end function lookup_message
!
      end module lookup_c
