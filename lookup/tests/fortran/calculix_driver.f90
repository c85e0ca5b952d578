! Calls the CalculiX example gapcon (lookup/examples/calculix_gapcon.f) as
! ccx would: arguments p, temp(1) (slave), temp(2) (master); prints ak(1).
! Compiled and run by lookup/tests/fortran_examples.rs.
program calculix_driver
  implicit none
  real(8) :: ak(5), d(2), flowm(2), temp(2), predef(2, 1), time(2), coords(3), area
  character(len=80) :: ciname, slname, msname, arg
  integer :: i
  real(8) :: q(3)
  do i = 1, 3
    call get_command_argument(i, arg)
    read (arg, *) q(i)
  end do
  ak = -1.0d0
  d = [0.0d0, q(1)]
  temp = [q(2), q(3)]
  flowm = 0; predef = 0; time = 0; coords = 0; area = 1
  ciname = 'TCGEN'; slname = ' '; msname = ' '
  call gapcon(ak, d, flowm, temp, predef, time, ciname, slname, msname, coords, &
              1, 0, 0, 1, 1, area)
  write (*, '(a, es26.17e3)') 'ak1 ', ak(1)
end program calculix_driver
