! Calls the Abaqus example (lookup/examples/abaqus_gapcon.f) as Abaqus would:
! UEXTERNALDB(0) at the start, GAPCON with arguments p, TEMP(1) (slave),
! TEMP(2) (master), UEXTERNALDB(3) at the end; prints AK(1) and AK(3).
! STDB_ABQERR is stubbed. Compiled and run by lookup/tests/fortran_examples.rs.
program abaqus_driver
  implicit none
  real(8) :: ak(5), d(2), flowm(2), temp(2), predef(2, 1), time(2), coords(3)
  character(len=80) :: ciname, slname, msname, arg
  integer :: i
  real(8) :: q(3)
  do i = 1, 3
    call get_command_argument(i, arg)
    read (arg, *) q(i)
  end do
  time = 0
  call uexternaldb(0, 0, time, 0.0d0, 1, 1)
  ak = -1.0d0
  d = [0.0d0, q(1)]
  temp = [q(2), q(3)]
  flowm = 0; predef = 0; coords = 0
  ciname = 'TCGEN'; slname = ' '; msname = ' '
  call gapcon(ak, d, flowm, temp, predef, time, ciname, slname, msname, coords, &
              1, 7, 0, 1, 1)
  write (*, '(a, 2es26.17e3)') 'ak1 ak3 ', ak(1), ak(3)
  call uexternaldb(3, 0, time, 0.0d0, 1, 1)
end program abaqus_driver

! Stand-in for the Abaqus utility routine: report and stop.
subroutine stdb_abqerr(lop, string, intv, realv, charv)
  implicit none
  integer :: lop, intv
  character(len=*) :: string, charv
  real(8) :: realv
  write (*, '(a, i0, 2a)') 'STDB_ABQERR ', lop, ' ', trim(string)
  if (intv /= 0 .or. realv /= 0 .or. len_trim(charv) > 0) write (*, *) intv, realv, trim(charv)
  if (lop == -3) error stop 3
end subroutine stdb_abqerr
